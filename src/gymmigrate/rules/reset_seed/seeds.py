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
from collections.abc import Callable

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import names as N
from gymmigrate.facts.creation import Creation, CreationFinder
from gymmigrate.facts.decisions import Action, Decision, receiver_text
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.legacy_wrapper_hooks import in_dead_hook
from gymmigrate.facts.module import (
    COMPOUND_STATEMENTS,
    statement_lines,
    string_value,
    walk,
)
from gymmigrate.facts.multi_agent import MultiAgent
from gymmigrate.facts.reset_flow import line_before, segment
from gymmigrate.facts.version_checks import dead_version_branch
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.env_ids.catalog import known_elsewhere
from gymmigrate.rules.multi_agent_gate import pettingzoo_in_reach
from gymmigrate.rules.reset_seed.call_edits import SeedValue, int_call
from gymmigrate.rules.reset_seed.common import (
    ResetSeedBase,
    is_space,
    moving_seed_question,
)

_BLOCK_FIELDS = ("body", "orelse", "finalbody")
# methods of an env a seed never moves past: they run or end episodes
_NOT_SETUP = frozenset({"reset", "step", "seed", "close", "render", "step_async", "step_wait"})


class SeedCalls(ResetSeedBase):
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
            return any(
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Attribute)
                and node.func.attr == "reset"
                and segment(self.facts, node.func.value) == wanted
                for node in walk(part)
            )

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

    def _merge_into_counted_loop(
        self,
        call: ast.Call,
        statement: ast.Expr,
        receiver: ast.expr,
        decision: Decision,
        code: str,
        called: str,
        numpy: bool,
    ) -> bool:
        """``env.seed(s)`` followed in its block by a counted loop (``for i in range(n)``,
        ``for i, x in enumerate(xs)``, ``i = 0 ... while i < n: ... i += 1``) whose body's first
        statement touching the env resets it, at the body's top level: legacy's seeded episode
        is the one the first iteration's reset returns. A reset in the seed's place would start
        an extra episode before it, so the seed goes to that reset on the first iteration only:
        ``env.reset(seed=s if i == 0 else None)`` (``seed=None`` continues the stream as
        ``reset()`` did). Statements between the seed and the loop must leave the env alone, and
        nothing may rebind the counter or the seed's names before that reset."""
        found = self._place_in_block(statement)
        if found is None:
            return False
        block, position = found
        if not self._alone_on_its_line(statement, block, position):
            return False
        wanted = segment(self.facts, receiver)
        root = _root_name(receiver)
        if root is None:
            return False
        between: list[ast.stmt] = []
        for line in statement_lines(block, position + 1):
            if isinstance(line[0], (ast.For, ast.While)):
                loop = line[0]
                break
            if not _independent_of(line, root):
                return False
            between.extend(line)
        else:
            return False
        counter = _loop_counter(loop, [*block[:position], *between])
        if counter is None:
            return False
        reset_statement = _first_touching(loop.body, root)
        if reset_statement is None or isinstance(reset_statement, COMPOUND_STATEMENTS):
            return False
        resets = [
            node
            for node in walk(reset_statement)
            if isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and node.func.attr == "reset"
            and segment(self.facts, node.func.value) == wanted
        ]
        if len(resets) != 1 or resets[0].args or resets[0].keywords:
            return False
        reset = resets[0]
        before = loop.body[: loop.body.index(reset_statement)]
        if any(self._calls_local(part) for part in before):
            return False  # a function of the module may reset the env first
        read = {node.id for node in walk(statement.value) if isinstance(node, ast.Name)} | {root}
        # the counter is 0 when the loop starts (the for binds it; a while's ``i = 0`` was
        # checked): only what the body does before the reset may change it
        bound = _bound_names([*between, *before])
        if isinstance(loop, ast.For):
            bound |= {node.id for node in walk(loop.target) if isinstance(node, ast.Name)}
        if "*" in bound or counter in _bound_names(before) or read & (bound | {counter}):
            return False
        value = SeedValue()
        self.plan.replace(call, value.take)
        self.plan.remove(statement, keep_comments=True)
        seed = value.get(as_int=numpy, moved=lambda: statement in self.plan.removed)
        self._edit(reset).add_seed = _conditional_seed(seed, f"{counter} == 0", True)
        self.report(
            call,
            code,
            f"`{called}(s)` merged into the reset of the loop's first iteration (line {reset.lineno}): "
            f"`{receiver_text(receiver)}.reset(seed=s if {counter} == 0 else None)`; that reset returns the seeded "
            f"episode, as legacy's did, and no extra episode starts{self._why(decision)}",
            self._kind(decision, FixKind.AUTO),
            tier=Tier.NOTE if decision.action is Action.REWRITE else None,  # it explains the rewrite: nothing to decide
            question=self.receiver_question(receiver, decision),
        )
        return True

    def _calls_local(self, statement: ast.stmt) -> bool:
        """Does ``statement`` call a function or method of this module (which may touch the env)?"""
        local = self.facts.memo(("seed-local-defs", 0), lambda: _defined_names(self.facts.tree))
        for node in walk(statement):
            if isinstance(node, ast.Call):
                func = node.func
                if isinstance(func, ast.Name) and func.id in local:
                    return True
                if isinstance(func, ast.Attribute) and func.attr in local:
                    return True
        return False

    def _merge_from_branch(
        self,
        call: ast.Call,
        statement: ast.Expr,
        receiver: ast.expr,
        decision: Decision,
        code: str,
        called: str,
        numpy: bool,
    ) -> bool:
        """``if c: env.seed(s)`` (or the seed ending an else) followed, after the if, by the
        reset of the same env: legacy's seeded episode is the one that reset returns. A reset
        put in the seed's place would play that episode and hand the program the next one,
        so the seed goes to the reset after the if, on the path that seeded:
        ``env.reset(seed=s if c else None)`` (``reset(seed=None)`` continues the stream as
        ``reset()`` did). That needs a test without side effects whose names, like the seed's,
        nothing rebinds before the reset; otherwise the call is reported and left. Where no
        reset of the env follows the if in its block, the seeded reset in place stays."""
        branch = self.facts.parent(statement)
        if not isinstance(branch, ast.If):
            return False
        in_body = bool(branch.body) and branch.body[-1] is statement
        in_else = bool(branch.orelse) and branch.orelse[-1] is statement
        if not (in_body or in_else):
            return False
        reset, setup = self._next_reset(branch, receiver)  # type: ignore[arg-type]  # any statement of a block
        if reset is None:
            return False
        name = receiver_text(receiver)
        why = self._why(decision)
        blocker = self._branch_blocker(branch, statement, reset, receiver, setup)
        whole_if = in_body and len(branch.body) == 1 and not branch.orelse
        if blocker is None and in_body and len(branch.body) == 1 and branch.orelse:
            blocker = "the seed is all the if does and an else follows"
        if blocker is not None:
            self.report(
                call,
                code,
                f"`{called}(s)` seeds in a branch the reset after the if (line {reset.lineno}) follows: that reset "
                f"gave the seeded episode, so `{name}.reset(seed=s)` here would hand the program the next one; "
                f"pass the seed to that reset on this path only ({blocker}){why}",
                FixKind.FLAG,
                question=self.receiver_question(receiver, decision),
            )
            return True
        value = SeedValue()
        self.plan.replace(call, value.take)
        if whole_if:
            self.plan.remove(branch, keep_comments=True)
            removed: ast.stmt = branch
        else:
            self.plan.remove(statement, keep_comments=True)
            removed = statement
            if in_else and len(branch.orelse) == 1:
                self.plan.replace(branch, _without_else)
        test = segment(self.facts, branch.test)
        seed = value.get(as_int=numpy, moved=lambda: removed in self.plan.removed)
        shown = f"s if {test} else None" if in_body else f"None if {test} else s"
        argument = _seed_argument(call)
        if argument is not None and _none_guard(branch.test, in_body) == ast.unparse(argument):
            # ``if s is not None: env.seed(s)``: reset(seed=None) is what the other path does anyway
            self._edit(reset).add_seed = seed
            shown = "s"
        else:
            self._edit(reset).add_seed = _conditional_seed(seed, test, in_body)
        self.report(
            call,
            code,
            f"`{called}(s)` merged into the reset after the if (line {reset.lineno}), on the path that seeded: "
            f"`{name}.reset(seed={shown})`; that reset returns the seeded episode, as legacy's did{why}",
            self._kind(decision, FixKind.AUTO),
            question=self.receiver_question(receiver, decision),
        )
        return True

    def _branch_blocker(
        self, branch: ast.If, statement: ast.Expr, reset: ast.Call, receiver: ast.expr, setup: ast.Call | None
    ) -> str | None:
        """Why the seed of ``statement`` cannot move to ``reset`` as a conditional seed, or None."""
        if setup is not None:
            return f"set-up on the env runs before that reset (line {setup.lineno})"
        for node in walk(branch.test):
            if isinstance(node, (ast.Call, ast.NamedExpr, ast.Await, ast.Yield, ast.YieldFrom, ast.Lambda, ast.IfExp)):
                return "the if's test does more than read values"
        wanted = segment(self.facts, receiver)
        for part in (*branch.body, *branch.orelse):
            for node in walk(part):
                if (
                    node is not statement.value
                    and isinstance(node, ast.Call)
                    and isinstance(node.func, ast.Attribute)
                    and node.func.attr in ("seed", "_seed")
                    and segment(self.facts, node.func.value) == wanted
                ):
                    return "the env is seeded elsewhere in the if"
        read = {node.id for node in walk(branch.test) if isinstance(node, ast.Name)}
        read |= {node.id for node in walk(statement.value) if isinstance(node, ast.Name)}
        root = _root_name(receiver)
        if root is not None:
            read.add(root)
        between = self._statements_between(branch, reset)
        if between is None:
            return "the reset is not in the if's block"
        bound = _bound_names([*branch.body, *branch.orelse, *between])
        if "*" in bound:
            return "names are rebound globally before that reset"
        rebound = bound & read
        if rebound:
            return f"{', '.join(sorted(rebound))} may change before that reset"
        return None

    def _statements_between(self, first: ast.stmt, reset: ast.Call) -> list[ast.stmt] | None:
        found = self._place_in_block(first)
        if found is None:
            return None
        block, position = found
        holder = self.facts.parent(reset)
        for index in range(position + 1, len(block)):
            if block[index] is holder:
                return block[position + 1 : index]
        return None

    def _pettingzoo_seed(self, receiver: ast.expr) -> bool:
        """``self._env.seed(s)`` on a PettingZoo env, under the same conditions on which PZ106
        (``rules/pettingzoo/seed_render.py``) rewrites it."""
        if isinstance(receiver, ast.Name) and receiver.id == "self":
            return False
        if not pettingzoo_in_reach(self.facts, self.context):
            return False
        return MultiAgent.of(self.facts, self.receivers).kind(receiver) is not None

    def _seed_in_kept_chain(self, call: ast.Call, receiver: ast.expr) -> bool:
        """``env.seed(s)`` on an env the run keeps on the legacy API (``legacy_step_class``)
        whose wrapper chain holds a class of the run defining ``seed()`` (a compat wrapper
        storing the seed for its resets): that seed() is the project's API and stays. Called on
        the class itself, the call is left; through Gym wrappers put around it, which forward
        no ``seed`` in Gymnasium (AttributeError), it becomes ``env.get_wrapper_attr("seed")(s)``,
        which reaches the same method. A reset(seed=s) would bypass it, and a kept reset of
        the chain may take no seed."""
        if self.receivers.legacy_step_class(receiver) is None:
            return False
        holder = self.receivers.seed_holder(receiver)
        if holder is None:
            return False
        name = receiver_text(receiver)
        if holder == "own":
            self.report(
                call,
                "GM203",
                f"left as it is: `{name}` is a wrapper of this project kept on the legacy API, and its own seed() "
                "stays its API",
                FixKind.FLAG,
                tier=Tier.NOTE,
            )
            return True
        self.plan.replace(call.func, _through_wrapper_attr)
        self.report(
            call,
            "GM203",
            f"`{name}.seed(s)` -> `{name}.get_wrapper_attr(\"seed\")(s)`: `{name}` is kept on the legacy API, and the "
            "seed() it calls is a wrapper's of this project inside it; Gymnasium's wrappers around that one forward "
            "no seed()",
            FixKind.AUTO,
            tier=Tier.NOTE,
        )
        return True

    def _seed_through_unwrapped(
        self, call: ast.Call, function: ast.FunctionDef | ast.AsyncFunctionDef, decision: Decision, code: str, name: str
    ) -> bool:
        """``env.seed(s)`` in a project's own ``seed()`` (a plain class's, not Gym's hook) on
        an env ``make`` built, while env classes of the run keep their seed() (GM503): the
        make's wrappers have no ``seed`` in Gymnasium (AttributeError), ``env.unwrapped.seed(s)``
        reaches the class's own. Certain (a note) when every make behind ``env`` names an id
        the run registers for such a class; else rewritten and listed for review: an env of
        another package has no seed() either way, and seeds through ``reset(seed=...)``."""
        project = self.receivers.project
        receiver = call.func.value  # type: ignore[attr-defined]
        if project is None or decision.action not in (Action.REWRITE, Action.REWRITE_FOR_REVIEW):
            return False
        if isinstance(receiver, ast.Attribute) and receiver.attr == "unwrapped":
            return False
        classdef = self.facts.enclosing_class(function)
        if classdef is not None and (
            self.receivers.class_kind(classdef) is EnvKind.GYM_ENV or self.receivers.is_gym_wrapper_class(classdef)
        ):
            return False  # Gym's own seed() hook of an env or wrapper class: GM503 decides it
        keepers = project.seed_classes()
        makes = self._makes_behind(receiver)
        if not keepers or not makes.calls:
            return False
        classes = {self._seed_class_made(make) for make in makes.calls}
        # A wrapper class of the run with a seed() of its own may sit in the chain (a make of
        # a factory id): gym's forwarding reached the outermost seed(), the wrapper's, which
        # ``.unwrapped`` would skip; ``get_wrapper_attr`` finds it as forwarding did.
        through = _through_wrapper_attr if project.seed_wrappers() else _through_unwrapped
        new = f'{name}.get_wrapper_attr("seed")(s)' if project.seed_wrappers() else f"{name}.unwrapped.seed(s)"
        self.plan.replace(call.func, through)
        if makes.complete and None not in classes:
            self.report(
                call,
                code,
                f"`{name}.seed(s)` -> `{new}`: this seed() is the project's own, and `{name}` is "
                f"made as {', '.join(sorted(c for c in classes if c))}, which keeps its seed() (GM503) behind "
                "wrappers that have none in Gymnasium",
                FixKind.AUTO,
                tier=Tier.NOTE,
            )
            return True
        self.report(
            call,
            code,
            f"`{name}.seed(s)` -> `{new}` inside this project's own seed(): Gymnasium's wrappers "
            f"have no seed(), the env classes of the run keep theirs ({', '.join(keepers)}, GM503); if `{name}` may "
            "be an env of another package, seed it through reset(seed=...) instead",
            FixKind.ASSIST,
            question=moving_seed_question(function),
        )
        return True

    def _seed_reaches_own_seed(self, call: ast.Call, function: ast.FunctionDef | ast.AsyncFunctionDef, receiver: ast.expr, name: str) -> bool:
        """``[env.seed(s + i) for i, env in enumerate(self.envs)]`` in the seed() of the
        project's own class (a vector env of its own, a plain class: no Gym env or wrapper),
        where every env it holds is an instance of a class of the run that defines seed()
        itself (``seed_holder``: "own"): the call reaches that method, which Gymnasium keeps
        as any method; what it does inside is that method's own item. Left, with a note."""
        classdef = self.facts.enclosing_class(function)
        if classdef is None or self.facts.parent(function) is not classdef:
            return False
        if self.receivers.class_kind(classdef).is_gym or self.receivers.is_gym_wrapper_class(classdef):
            return False  # an env's own seed() hook: GM503 and the rules below decide it
        if self.receivers.seed_holder(receiver) != "own":
            return False
        self.report(
            call,
            "GM203",
            f"left as it is: every `{name}` here is an instance of a class of this project that defines seed() "
            f"itself, and `{classdef.name}.seed()` is this project's own API",
            FixKind.FLAG,
            tier=Tier.NOTE,
        )
        return True

    def _seed_in_own_seed(
        self, call: ast.Call, function: ast.FunctionDef | ast.AsyncFunctionDef, decision: Decision, code: str, name: str
    ) -> bool:
        """``self._env.seed(s)`` in the seed() of a plain class (a project's adapter around a
        Gym env, deriving its own base) or a plain function: the project calls it, not Gym,
        and ``env.seed`` raises AttributeError in Gymnasium. It becomes ``reset(seed=s)`` in
        place, which also starts an episode: harmless when the project seeds before its
        first reset (the later resets continue the seeded stream, as legacy seed() then
        reset() did), an episode restarted when it seeds mid-episode. The run cannot see
        when it is called, so the rewrite is listed once for review."""
        if decision.action not in (Action.REWRITE, Action.REWRITE_FOR_REVIEW):
            return False
        receiver = call.func.value  # type: ignore[attr-defined]
        project = self.receivers.project
        if isinstance(receiver, ast.Attribute) and receiver.attr == "unwrapped":
            return False  # an env class's own seed(), reached on purpose (``_seed_through_unwrapped``)
        if project is not None and project.seed_classes():
            return False  # env classes of the run keep a seed(): the env may have one
        classdef = self.facts.enclosing_class(function)
        if classdef is not None and not self.own_plain_class(classdef, set()):
            return False  # an env class's own seed() hook (GM503 decides it), or a base from elsewhere
        statement = self.facts.parent(call)
        seed = _seed_argument(call)
        returned = isinstance(statement, ast.Return) and isinstance(seed, ast.Name)
        if not (isinstance(statement, ast.Expr) or returned) or seed is None:
            return False
        numpy = self.numpy_seeds.is_numpy(seed)
        kept = ""
        if returned:
            # ``return self.env.seed(s)``: the project's seed() handed on the env's [seed];
            # it seeds through the reset and still returns that list to its callers
            seed_text = segment(self.facts, seed)
            reset = f"{segment(self.facts, receiver)}.reset(seed={f'int({seed_text})' if numpy else seed_text})"
            self.plan.insert_before(statement, reset)  # type: ignore[arg-type]  # a Return, checked above
            self.plan.replace(call, lambda node: cst.List([cst.Element(cst.Name(seed_text))]))
            kept = f", and it returns [{seed_text}] as before (legacy gave the seed it drew where none was passed)"
        else:
            edit = self._edit(call)
            edit.to_reset = True
            edit.int_seed = numpy
        owner = f"`{classdef.name}.seed()`" if classdef is not None else "this seed()"
        self.report(
            call,
            code,
            f"`{name}.seed(s)` -> `{name}.reset(seed=s)` in {owner}, which this project calls itself (Gymnasium has "
            f"no env.seed()): this also resets `{name}`; if the project calls it mid-episode, that episode now "
            f"restarts here{kept}",
            FixKind.ASSIST,
            question=moving_seed_question(function),
        )
        return True

    def _seed_in_wrapper_seed(
        self, call: ast.Call, function: ast.FunctionDef | ast.AsyncFunctionDef, decision: Decision, code: str, name: str
    ) -> bool:
        """``env.seed(s)`` in the seed() of a Gym wrapper class of the run (its wrapped or
        scheduled envs), while env classes of the run keep their seed() (GM503): that seed()
        is still called (``get_wrapper_attr("seed")``, ``_seed_through_chain``), and gym's
        wrappers forwarded ``env.seed`` down to the first class defining it, which
        ``get_wrapper_attr("seed")`` reaches in Gymnasium. Listed for review: an env of
        another package has no seed() and seeds through ``reset(seed=...)``."""
        project = self.receivers.project
        receiver = call.func.value  # type: ignore[attr-defined]
        classdef = self.facts.enclosing_class(function)
        if (
            project is None
            or decision.action not in (Action.REWRITE, Action.REWRITE_FOR_REVIEW)
            or classdef is None
            or not self.receivers.is_gym_wrapper_class(classdef)
            or classdef.name not in project.seed_wrappers()
            or not project.seed_classes()
            or (isinstance(receiver, ast.Attribute) and receiver.attr == "unwrapped")
        ):
            return False
        self.plan.replace(call.func, _through_wrapper_attr)
        self.report(
            call,
            code,
            f"`{name}.seed(s)` -> `{name}.get_wrapper_attr(\"seed\")(s)` in the seed() of {classdef.name}, a wrapper "
            f"of this project that callers still seed through: Gymnasium's wrappers forward no seed(), the env "
            f"classes of the run keep theirs ({', '.join(project.seed_classes())}, GM503); if `{name}` may be an env "
            "of another package, seed it through reset(seed=...) instead",
            FixKind.ASSIST,
            question=moving_seed_question(function),
        )
        return True

    def _seed_through_chain(self, call: ast.Call, receiver: ast.expr, decision: Decision, code: str, name: str) -> bool:
        """``env.seed(s)`` on an env ``make`` built, in a run whose env classes keep their
        seed() (GM503) and where a Gym wrapper class of the run defines a seed() of its own
        (a wrapper over several envs that seeds them all and its scheduler): a make of a
        factory id may return that wrapper, whose reset(seed=s) (Gym's, or the project's
        handing ``**kwargs`` on) does not do what its seed() did. Merging the seed into the
        next reset loses that seeding; ``env.get_wrapper_attr("seed")(s)`` calls the seed()
        gym's forwarding reached, and the reset after it stays as it was. Certain (a note)
        when every make names an id the run registers for a class keeping seed(); else
        listed for review (an env of another package has no seed())."""
        project = self.receivers.project
        if project is None or decision.action not in (Action.REWRITE, Action.REWRITE_FOR_REVIEW):
            return False
        if isinstance(receiver, ast.Attribute) and receiver.attr == "unwrapped":
            return False
        wrappers = project.seed_wrappers()
        keepers = project.seed_classes()
        if not wrappers or not keepers:
            return False
        makes = self._makes_behind(receiver)
        if not makes.calls:
            return False
        classes = {self._seed_class_made(make) for make in makes.calls}
        self.plan.replace(call.func, _through_wrapper_attr)
        said = (
            f"`{name}.seed(s)` -> `{name}.get_wrapper_attr(\"seed\")(s)`, not merged into a reset: the run's wrappers "
            f"{', '.join(wrappers)} define a seed() that reset(seed=...) does not call, and the env classes keep theirs "
            f"({', '.join(keepers)}, GM503); gym's `{name}.seed(s)` reached the outermost of them"
        )
        if makes.complete and None not in classes:
            self.report(call, code, said, FixKind.AUTO, tier=Tier.NOTE)
            return True
        self.report(
            call,
            code,
            f"{said}; if `{name}` may be an env of another package, seed it through reset(seed=...) instead",
            FixKind.ASSIST,
            question=self.receiver_question(receiver, decision),
        )
        return True

    def _makes_behind(self, receiver: ast.expr) -> Creation:
        project = self.receivers.project

        def is_make(made: ast.Call) -> bool:
            return any(
                N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES or (project is not None and project.returns_made(q))
                for q in self.facts.qualified_names(made.func)
            )

        finder = self.facts.memo(("seed-make-finder", 0), lambda: CreationFinder(self.facts, self.receivers, is_make))
        return finder.find(receiver)

    def _seed_class_made(self, make: ast.Call) -> str | None:
        """The class of the run keeping seed() that ``make("Id-v0")`` builds, if the id is a
        literal the run registers for one."""
        project = self.receivers.project
        env_id = string_value(make.args[0]) if make.args and project is not None else None
        return project.seed_class_of_id(env_id) if env_id is not None and project is not None else None

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

    # -- merging into the next reset ---------------------------------------------------------

    def _next_reset(self, statement: ast.Expr, receiver: ast.expr) -> tuple[ast.Call | None, ast.Call | None]:
        """The reset of the same env that the seeding ``statement`` leads to, if merging is
        safe, and the first set-up call on the env the seed moves past (None if none).

        Only statements of the same block are looked at, so a seed is never moved into a
        loop; statements in between must not touch the env (space seeding and other
        seeding calls are fine), except set-up calls of the env's own methods
        (``env.set_agents(...)``): the reset that comes next in program order follows them,
        and a reset put in the seed's place would run before them. The seed must have its
        line to itself.
        """
        found = self._place_in_block(statement)
        if found is None:
            return None, None
        block, position = found
        if not self._alone_on_its_line(statement, block, position):
            return None, None
        wanted = segment(self.facts, receiver)
        root = _root_name(receiver)
        setup: ast.Call | None = None
        for line in statement_lines(block, position + 1):
            reset = self._reset_statement(line, wanted)
            if reset is not None:
                return reset, setup
            if _independent_of(line, root):
                continue
            call = self._setup_call(line, wanted, root)
            if call is None:
                return None, None
            setup = setup or call
        return None, None

    def _setup_call(self, line: list[ast.stmt], receiver_code: str, root: str | None) -> ast.Call | None:
        """``env.set_agents(agents)`` on a line of its own: a method of the env itself or of
        what it wraps (not reset, step, seed, close or render) called for its effect, whose arguments neither
        hand the env on nor rebind anything."""
        if root is None or len(line) != 1 or not isinstance(line[0], ast.Expr):
            return None
        call = line[0].value
        if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute)):
            return None
        owner = call.func.value  # the env, or what it wraps: ``env.unwrapped.set_agents(...)``
        while isinstance(owner, ast.Attribute) and segment(self.facts, owner) != receiver_code:
            owner = owner.value
        if call.func.attr in _NOT_SETUP or segment(self.facts, owner) != receiver_code:
            return None
        for argument in [*call.args, *(kw.value for kw in call.keywords)]:
            for node in walk(argument):
                if isinstance(node, ast.NamedExpr) or (isinstance(node, ast.Name) and node.id == root):
                    return None
        return call

    def _alone_on_its_line(self, statement: ast.stmt, block: list[ast.stmt], position: int) -> bool:
        """Not in a one-line suite (``if x: env.seed(1)``) nor sharing its line (``a; env.seed(1)``)."""
        if line_before(self.facts, statement).strip():
            return False
        following = block[position + 1] if position + 1 < len(block) else None
        return following is None or following.lineno > (statement.end_lineno or statement.lineno)

    def _place_in_block(self, statement: ast.stmt) -> tuple[list[ast.stmt], int] | None:
        """The block that holds ``statement`` (a body, an else, a handler...) and its index there."""
        parent = self.facts.parent(statement)

        def index() -> dict[int, tuple[list[ast.stmt], int]]:
            places: dict[int, tuple[list[ast.stmt], int]] = {}
            for name in _BLOCK_FIELDS:
                items = getattr(parent, name, None)
                if isinstance(items, list):
                    places.update((id(item), (items, i)) for i, item in enumerate(items))
            return places

        return self.facts.memo(("reset-seed-block", id(parent)), index).get(id(statement))

    def _reset_statement(self, line: list[ast.stmt], receiver_code: str) -> ast.Call | None:
        if len(line) != 1 or not isinstance(line[0], (ast.Expr, ast.Assign)):
            return None
        value = line[0].value
        if not (isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr == "reset"):
            return None
        if segment(self.facts, value.func.value) != receiver_code:
            return None
        if value.args or any(kw.arg is None or kw.arg == "seed" for kw in value.keywords):
            return None
        return value


def _without_else(node: cst.If) -> cst.If:
    """The if whose else held only the seed merged after it: the else goes."""
    return node.with_changes(orelse=None)


def _conditional_seed(
    seed: Callable[[], cst.BaseExpression | None], test: str, in_body: bool
) -> Callable[[], cst.BaseExpression | None]:
    """``s if test else None`` (``None if test else s`` for a seed in the else)."""

    def value() -> cst.BaseExpression | None:
        taken = seed()
        if taken is None:
            return None
        if isinstance(taken, (cst.IfExp, cst.Lambda, cst.NamedExpr)) and not taken.lpar:
            taken = taken.with_changes(lpar=[cst.LeftParen()], rpar=[cst.RightParen()])
        condition = cst.parse_expression(f"({test})")
        if isinstance(condition, (cst.Name, cst.Attribute, cst.Comparison, cst.UnaryOperation, cst.Subscript)):
            condition = condition.with_changes(lpar=[], rpar=[])  # plain enough to read without them
        none = cst.Name("None")
        body, orelse = (taken, none) if in_body else (none, taken)
        return cst.IfExp(test=condition, body=body, orelse=orelse)

    return value


def _none_guard(test: ast.expr, in_body: bool) -> str | None:
    """``x`` of ``if x is not None:`` (seed in the body) or ``if x is None:`` (seed in the else)."""
    if not (isinstance(test, ast.Compare) and len(test.ops) == 1 and isinstance(test.comparators[0], ast.Constant)):
        return None
    if test.comparators[0].value is not None or not isinstance(test.ops[0], ast.IsNot if in_body else ast.Is):
        return None
    return ast.unparse(test.left)


def _bound_names(statements: list[ast.stmt]) -> set[str]:
    """Names any of ``statements`` (re)binds, at any depth."""
    bound: set[str] = set()
    for statement in statements:
        for node in walk(statement):
            targets: list[ast.expr] = []
            if isinstance(node, ast.Assign):
                targets = list(node.targets)
            elif isinstance(node, (ast.AugAssign, ast.AnnAssign, ast.NamedExpr, ast.For, ast.AsyncFor)):
                targets = [node.target]
            elif isinstance(node, (ast.With, ast.AsyncWith)):
                targets = [item.optional_vars for item in node.items if item.optional_vars is not None]
            elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                bound.add(node.name)
            elif isinstance(node, (ast.Import, ast.ImportFrom)):
                bound.update((alias.asname or alias.name).split(".")[0] for alias in node.names)
            elif isinstance(node, (ast.Global, ast.Nonlocal, ast.Delete)):
                return {"*"} | bound  # too much to follow: treat every name as rebound
            for target in targets:
                bound.update(inner.id for inner in walk(target) if isinstance(inner, ast.Name))
    return bound


def _through_unwrapped(node: cst.Attribute) -> cst.Attribute:
    """``env.seed`` -> ``env.unwrapped.seed``."""
    return node.with_changes(value=cst.Attribute(value=node.value, attr=cst.Name("unwrapped")))


def _through_wrapper_attr(node: cst.Attribute) -> cst.Call:
    """``env.seed`` -> ``env.get_wrapper_attr("seed")``."""
    return cst.Call(
        func=cst.Attribute(value=node.value, attr=cst.Name("get_wrapper_attr")),
        args=[cst.Arg(value=cst.SimpleString(f'"{node.attr.value}"'))],
    )


def _seed_argument(call: ast.Call) -> ast.expr | None:
    """The one seed of ``x.seed(s)`` / ``x.seed(seed=s)``, else None."""
    if len(call.args) + len(call.keywords) != 1:
        return None
    if call.args:
        return None if isinstance(call.args[0], ast.Starred) else call.args[0]
    keyword = call.keywords[0]
    return keyword.value if keyword.arg == "seed" else None


def _root_name(node: ast.expr) -> str | None:
    while isinstance(node, (ast.Attribute, ast.Subscript, ast.Call)):
        node = node.func if isinstance(node, ast.Call) else node.value
    return node.id if isinstance(node, ast.Name) else None


def _independent_of(line: list[ast.stmt], root: str | None) -> bool:
    """Can a seed move past ``line``? Only simple lines that leave the env alone qualify.

    Reading the env's attributes is fine; rebinding the name or calling anything but a
    seeding function (env.action_space.seed, np.random.seed...) is not.
    """
    if root is None or isinstance(line[0], COMPOUND_STATEMENTS):
        return False
    bound: set[str] = set()

    def bind(target: ast.expr) -> None:
        if isinstance(target, (ast.Tuple, ast.List)):
            for element in target.elts:
                bind(element.value if isinstance(element, ast.Starred) else element)
        else:
            name = _root_name(target)
            if name is not None:
                bound.add(name)

    for statement in line:
        for node in walk(statement):
            if isinstance(node, ast.Assign):
                for target in node.targets:
                    bind(target)
            elif isinstance(node, (ast.AugAssign, ast.AnnAssign, ast.NamedExpr)):
                bind(node.target)
            elif isinstance(node, ast.Call):
                func = node.func
                called = func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else ""
                if "seed" not in called:
                    return False
    return root not in bound


def _defined_names(tree: ast.AST) -> frozenset[str]:
    return frozenset(
        node.name for node in ast.walk(tree) if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef))
    )


def _first_touching(body: list[ast.stmt], root: str) -> ast.stmt | None:
    """The first statement of ``body`` that names ``root``."""
    for statement in body:
        if any(isinstance(node, ast.Name) and node.id == root for node in walk(statement)):
            return statement
    return None


def _loop_counter(loop: ast.For | ast.While, earlier: list[ast.stmt]) -> str | None:
    """The counter that is 0 on a loop's first iteration and never again: ``for i in range(n)``,
    ``range(0, n)``, ``for i, x in enumerate(xs)``, or ``i = 0`` (the last binding of ``i`` in
    ``earlier``) then ``while i < n:`` whose body does ``i += 1`` at its top level, binds ``i``
    nowhere else and never continues."""
    if isinstance(loop, ast.For):
        it = loop.iter
        if not (isinstance(it, ast.Call) and isinstance(it.func, ast.Name) and not it.keywords):
            return None
        if it.func.id == "range" and isinstance(loop.target, ast.Name):
            if len(it.args) == 1 or (len(it.args) == 2 and _is_zero(it.args[0])):
                return loop.target.id
        if it.func.id == "enumerate" and len(it.args) == 1 and isinstance(loop.target, ast.Tuple):
            first = loop.target.elts[0] if loop.target.elts else None
            if isinstance(first, ast.Name):
                return first.id
        return None
    test = loop.test
    if not (
        isinstance(test, ast.Compare)
        and len(test.ops) == 1
        and isinstance(test.ops[0], ast.Lt)
        and isinstance(test.left, ast.Name)
    ):
        return None
    counter = test.left.id
    steps = [
        s
        for s in loop.body
        if isinstance(s, ast.AugAssign)
        and isinstance(s.op, ast.Add)
        and isinstance(s.target, ast.Name)
        and s.target.id == counter
        and isinstance(s.value, ast.Constant)
        and s.value.value == 1
    ]
    if len(steps) != 1 or any(isinstance(node, ast.Continue) for part in loop.body for node in walk(part)):
        return None
    if counter in _bound_names([s for s in loop.body if s is not steps[0]]):
        return None
    for index in range(len(earlier) - 1, -1, -1):
        part = earlier[index]
        if counter in _bound_names([part]):
            if (
                isinstance(part, ast.Assign)
                and len(part.targets) == 1
                and isinstance(part.targets[0], ast.Name)
                and _is_zero(part.value)
            ):
                return counter
            return None
    return None


def _is_zero(node: ast.expr) -> bool:
    return isinstance(node, ast.Constant) and type(node.value) is int and node.value == 0


def _functions_by_name(tree: ast.AST) -> dict[str, list[ast.FunctionDef | ast.AsyncFunctionDef]]:
    found: dict[str, list[ast.FunctionDef | ast.AsyncFunctionDef]] = {}
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            found.setdefault(node.name, []).append(node)
    return found
