"""``env.seed(s)`` that still reaches a seed() of the project (GM203, GM208).

``SeedMethods`` (a mixin of ``SeedCalls``) decides the seeds that are not merged into a
reset: on a chain the run keeps on the legacy API, in a project's own ``seed()``, in the
seed() of a wrapper of the run, or through such a wrapper (``env.unwrapped.seed(s)``,
``env.get_wrapper_attr("seed")(s)``, or ``reset(seed=s)`` in place), and which makes are
behind an env.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import names as N
from gymmigrate.facts.creation import Creation, CreationFinder
from gymmigrate.facts.decisions import Action, Decision, receiver_text
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import string_value
from gymmigrate.facts.reset_flow import segment
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.reset_seed.common import (
    ResetSeedBase,
    _seed_argument,
    moving_seed_question,
)


class SeedMethods(ResetSeedBase):
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


def _through_unwrapped(node: cst.Attribute) -> cst.Attribute:
    """``env.seed`` -> ``env.unwrapped.seed``."""
    return node.with_changes(value=cst.Attribute(value=node.value, attr=cst.Name("unwrapped")))


def _through_wrapper_attr(node: cst.Attribute) -> cst.Call:
    """``env.seed`` -> ``env.get_wrapper_attr("seed")``."""
    return cst.Call(
        func=cst.Attribute(value=node.value, attr=cst.Name("get_wrapper_attr")),
        args=[cst.Arg(value=cst.SimpleString(f'"{node.attr.value}"'))],
    )
