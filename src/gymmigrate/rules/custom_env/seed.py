"""GM503: ``def seed(self, seed=None)`` is removed (gym 0.26 seeds in ``reset``).

The canonical ``self.np_random, seed = seeding.np_random(seed)`` body is deleted;
anything else that uses the seed moves into ``reset`` under ``if seed is not None:``;
set-up that does not touch the seed (spaces, simulators) moves into ``__init__`` where
``self.seed()`` was called; ``self.seed()`` calls go. Where the result of ``seed()`` is
used, or the body returns early, the method is only reported; so is one that returns the
seeding of an object it holds (``return self.scene.seed(seed)``: not a ``[seed]`` to drop). So is a method that a
caller elsewhere in the file may still reach: ``self.seed(7)`` in a subclass that
inherits it, or an ``x.seed(3)`` the seed rules leave because ``x`` could not be traced.
"""

from __future__ import annotations

import ast
import os

from gymmigrate.facts.decisions import Action, decide
from gymmigrate.facts.env_classes import (
    identifiers,
    is_self_attribute,
    is_super_method_call,
)
from gymmigrate.facts.module import (
    ModuleFacts,
    full_name,
    is_super_call,
    statement_lines,
    walk,
)
from gymmigrate.facts.summaries.untraced import (
    calls_seed,
    calls_seed_without_a_value,
    passes_a_value,
)
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.custom_env.common import (
    ClassDecision,
    inner_gym_env_call,
    is_docstring,
    method_of,
    param_names,
    random_state_np_random,
)
from gymmigrate.rules.custom_env.plans import SeedPlan
from gymmigrate.rules.reset_seed.common import is_space, moving_seed_question

NP_RANDOM = ("np_random", "_np_random")
# gym.utils.seeding helpers Gymnasium removed (GM506 reports them)
REMOVED_SEEDING_HELPERS = frozenset({"hash_seed", "create_seed", "_bigint_from_bytes", "_int_list_from_bigint"})


def decide_seed(decision: ClassDecision) -> None:
    seed_method = decision.method("seed")
    if seed_method is None:
        _decide_base_seed_calls(decision)
        return
    calls = _seed_call_sites(decision)
    facts = decision.family.facts
    kept_for = _untraced_seed_call(decision)
    project = decision.family.receivers.project
    if kept_for is None and project is not None and project.seed_called_elsewhere():
        decision.report(
            seed_method,
            "GM503",
            "seed() kept: another module of this run imports this class and calls `.seed(...)` on an object that "
            "could not be traced (or seeds made envs in a seed() method of its own), which may be an instance of it; "
            "once that call seeds through reset(seed=...), "
            "remove this method",
            FixKind.FLAG,
        )
        return
    below = _called_below_elsewhere(decision, seed_method)
    if kept_for is None and below:
        decision.report(
            seed_method,
            "GM503",
            f"seed() kept: {', '.join(below)} (another module of this run) calls it on its own instances "
            "(`self.seed(...)`), which would raise AttributeError once it is gone; once those calls seed through "
            "reset(seed=...), remove this method",
            FixKind.FLAG,
        )
        return
    if kept_for is not None:
        decision.report(
            seed_method,
            "GM503",
            f"seed() kept: `{facts.segment(kept_for)}` on line {kept_for.lineno} may call it and is left as it was "
            "(a subclass's call, or a receiver that could not be traced); once it seeds through reset(seed=...), "
            "remove this method",
            FixKind.FLAG,
        )
        return
    if random_state_np_random(decision) is not None and _reset_calls_seed(decision, seed_method):
        # ``self.np_random = np.random.RandomState()`` seeded by this seed(), which reset()
        # calls already: it keeps working as it is (reset() does not let Env.reset replace
        # the RandomState, GM501 says so there), nothing to move.
        return
    if any(not isinstance(facts.parent(call), ast.Expr) for call in calls):
        decision.report(seed_method, "GM503", "seed() is gone in Gymnasium but its result is used in this class; seed through reset(seed=...) and rewrite those uses", FixKind.FLAG)
        return
    params = param_names(seed_method)[1:2]
    seed_name = params[0] if params else "seed"
    groups = list(statement_lines(seed_method.body))
    moved: list[int] = []
    canonical_names: set[str] = set()
    deleted: list[ast.stmt] = []
    canonical: ast.Assign | None = None
    for index, group in enumerate(groups):
        if (index == 0 and is_docstring(group)) or _does_nothing(group):
            deleted.extend(group)  # a docstring, ``pass`` or ``...``: nothing to move
            continue
        target = _np_random_seeding(decision, group)
        if target is not None:
            canonical_names.update(target)
            canonical = canonical or group[0]  # type: ignore[assignment]  # an Assign (``_np_random_seeding``)
            deleted.extend(group)
            continue
        if index == len(groups) - 1 and len(group) == 1 and isinstance(group[0], ast.Return) and not _seeds_held_object(group[0]):
            deleted.extend(group)
            continue
        if len(group) == 1 and isinstance(group[0], ast.Expr) and is_super_method_call(group[0].value, "seed"):
            deleted.extend(group)
            continue
        moved.append(index)
    live = _without_dead_locals(groups, moved)
    dead_helper_lines = [s for i in moved if i not in live for s in groups[i] if _calls_removed_helpers(s)]
    moved = live
    if any(inner_gym_env_call(decision, node, name) for i in moved for s in groups[i] for node in walk(s) for name in ("seed", "_seed")):
        # Moved into reset(), `self.inner.seed(seed)` would be rewritten by the call-site
        # rule on the next run (a reset of the inner env inside this reset): by hand.
        decision.report(
            seed_method,
            "GM503",
            "seed() seeds an env this class holds; Gymnasium seeds it through its reset: pass `seed` to that "
            "env's reset(seed=...) in this class's reset() by hand",
            FixKind.FLAG,
            question=moving_seed_question(seed_method),
        )
        return
    if moved and moved[-1] == len(groups) - 1 and isinstance(groups[-1][0], ast.Return):
        # ``return self.scene.seed(seed)``: what it returns is the seeding of an object the
        # class holds, which the deletion of a plain ``return [seed]`` would lose unseen.
        decision.report(
            seed_method,
            "GM503",
            f"seed() seeds an object this class holds (`{facts.segment(groups[-1][0].value)}`, returned); Gymnasium "  # type: ignore[arg-type]
            "never calls seed(): seed that object in reset() under `if seed is not None:` by hand",
            FixKind.FLAG,
            question=moving_seed_question(seed_method),
        )
        return
    if any(isinstance(node, ast.Return) for i in moved for s in groups[i] for node in walk(s)):
        decision.report(seed_method, "GM503", "seed() returns from the middle of its body; move its seeding into reset() under `if seed is not None:` by hand", FixKind.FLAG, question=moving_seed_question(seed_method))
        return
    if moved and decision.method("reset") is None:
        decision.report(seed_method, "GM503", "seed() does more than seed np_random and this class has no reset(); move that code into reset() under `if seed is not None:`", FixKind.FLAG, question=moving_seed_question(seed_method))
        return
    seed_names = {seed_name} | canonical_names
    setup = [i for i in moved if not _is_seeding_statement(groups[i], seed_names)]
    moved = [i for i in moved if i not in setup]
    init = decision.methods.get("__init__")
    init_call = calls[0] if len(calls) == 1 and init is not None and facts.enclosing_function(calls[0]) is init else None
    # ``self.seed()`` with no seed (in __init__, typically) ran the moved statements too:
    # ``self.rand = random.Random(seed)`` built the generator every later draw needs. Under
    # reset()'s ``if seed is not None:`` they would never run there, so seed() stays.
    unseeded_call = any(facts.enclosing_function(call) is not seed_method and not _passes_a_seed(call) for call in calls)
    builds_state = unseeded_call and bool(_state_only_seed_builds([s for i in moved for s in groups[i]], init))
    needed = (setup or moved) and _needs_the_method(groups, moved, setup, seed_names)
    # ``self.seed(seed)`` in __init__ with extra seeding (``np.random.seed(seed)``): the
    # constructor's seed made every later draw of that generator reproducible. Moved under
    # reset()'s ``if seed is not None:`` it would run only on a seeded reset, which a caller
    # that seeds through the constructor never makes: the constructor keeps calling it.
    seeded_construction = bool(moved) and any(
        init is not None and facts.enclosing_function(call) is init and _passes_a_seed(call) for call in calls
    )
    if (needed or builds_state or seeded_construction) and not _calls_removed_helpers(seed_method):
        why = (
            "besides seeding np_random it builds state from the seeded generator or from its own locals, which cannot be split up"
            if needed
            else "the class calls it without a seed, which builds the generators its later draws need (under reset()'s "
            "`if seed is not None:` that would never run)"
            if builds_state
            else "__init__ calls it with the constructor's seed, and what it seeds besides np_random (a global "
            "generator, an object the env holds) must stay seeded there: under reset()'s `if seed is not None:` "
            "alone, a run seeded through the constructor would no longer reproduce"
        )
        _keep_as_helper(decision, seed_method, why)
        return
    init_end = bool(setup) and not calls and _setup_fits_init_end(decision, [s for i in setup for s in groups[i]], init)
    if setup and init_call is None and not init_end:
        decision.family.context.notes.dead_in_hand_ported_seed.update(dead_helper_lines)
        decision.report(seed_method, "GM503", "seed() also builds state that does not depend on the seed; move it into __init__ and the seeding into reset() by hand", FixKind.FLAG, question=moving_seed_question(seed_method))
        return
    # Only seed()'s canonical line goes (nothing moved or set up): a seed passed to it still
    # builds the generator where the call was (``seed=1001`` in __init__ made every run draw
    # the same), instead of being dropped for a reset(seed=...) no caller makes.
    reseed = _reseeding(decision, canonical, calls, seed_method, seed_name) if canonical is not None and not moved and not setup else None
    reseeded = False
    for call in calls:
        if facts.enclosing_function(call) is seed_method or (setup and call is init_call):
            continue
        if reseed is not None and _passes_one_seed(call, seed_name):
            reseeded = True
            decision.report(
                call,
                "GM503",
                f"self.seed(s) -> `{reseed[1].format('s')}`: Gymnasium's Env has no seed(); the seed given here still "
                "builds the generator, as the removed seed() did, so runs seeded through it draw as before",
            )
            continue
        given = _passes_a_seed(call)
        message = (
            "self.seed(...) removed: pass that seed to the first reset(seed=...) instead"
            if given
            else "self.seed() removed: reset(seed=None) picks a random seed itself"
        )
        decision.report(call, "GM503", message, FixKind.ASSIST if given else FixKind.AUTO)
    if setup and all(_only_prints(facts, groups[i]) for i in setup):
        # A message printed or logged changes no state: where it runs now decides nothing.
        decision.report(init_call, "GM503", "what seed() printed or logged besides seeding now runs here in __init__ instead of the self.seed() call", FixKind.ASSIST, tier=Tier.NOTE)  # type: ignore[arg-type]
    elif init_end:
        decision.report(
            init,  # type: ignore[arg-type]  # ``_setup_fits_init_end``: __init__ exists
            "GM503",
            "the set-up seed() did besides seeding now runs at the end of __init__: it reads only what __init__ "
            "builds, and reset() sets again everything it sets",
            FixKind.ASSIST,
            tier=Tier.NOTE,
        )
    elif setup:
        decision.report(init_call, "GM503", "the set-up seed() did besides seeding (spaces, objects) now runs here in __init__ instead of the self.seed() call", FixKind.ASSIST)  # type: ignore[arg-type]
    callers = {method.name for call in calls if (method := method_of(decision, call)) is not None}
    decision.plan.seed = SeedPlan(
        moved=moved, setup=setup, setup_at_init_end=init_end, renames={n: "seed" for n in seed_names if n != "seed"}, callers=callers, reseed=reseed if reseeded else None
    )
    decision.removed.add(seed_method.name)
    # a reseeded call reads the seeding import the canonical line read: it stays
    decision.deleted_statements.extend(s for s in deleted if not (reseeded and s is canonical))
    kept = set(moved) | set(setup)
    decision.family.context.notes.dropped_statements.update(
        node for index, group in enumerate(groups) if index not in kept for statement in group for node in walk(statement) if isinstance(node, ast.stmt)
    )
    if not moved:
        decision.report(seed_method, "GM503", "seed() removed: super().reset(seed=seed) in reset() seeds self.np_random")
    elif not calls and not _seed_called_in_run(decision):
        # Nothing of the run called seed(): its seeding never ran, and now runs only on a
        # seeded reset, which nothing asks for either. Nothing to decide.
        decision.report(
            seed_method,
            "GM503",
            "seed() removed: its extra seeding moved into reset() under `if seed is not None:`; nothing in this run "
            "calls seed(), so it runs only once a reset is given a seed",
            FixKind.ASSIST,
            tier=Tier.NOTE,
        )
    elif not _seed_called_without_a_value(decision, calls, seed_method):
        # Every call of seed() the run sees passes a seed (an int, a computed seed): the
        # extra seeding only ever ran on a given seed, as it now does in reset().
        decision.report(
            seed_method,
            "GM503",
            "seed() removed: its extra seeding moved into reset() under `if seed is not None:`; every call of seed() "
            "in this run passes a seed, so it runs as before once that seed goes to reset(seed=...)",
            FixKind.ASSIST,
            tier=Tier.NOTE,
        )
    else:
        decision.report(
            seed_method,
            "GM503",
            "seed() removed: its extra seeding moved into reset() under `if seed is not None:`; it now runs only when a seed is given",
            FixKind.ASSIST,
        )


def _decide_base_seed_calls(decision: ClassDecision) -> None:
    """``self.seed()`` in a class that defines no seed() and derives from ``gym.Env`` alone:
    the call reached gym's ``Env.seed``, which Gymnasium's Env does not have
    (AttributeError). Without a seed it seeded nothing a Gymnasium env needs (``np_random``
    seeds itself on first use), so it goes; with one, that seed belongs in reset(seed=...)."""
    if not decision.env.only_gym_env_bases(decision.classdef):
        return  # a mix-in or another base may define the seed() the call reaches
    if "seed" in decision.methods or "_seed" in decision.methods or _binds_in_class_body(decision.classdef, "seed"):
        return
    calls = list(decision.index.self_calls.get("seed", ()))
    if not calls:
        return
    facts = decision.family.facts
    if any(not isinstance(facts.parent(call), ast.Expr) or _passes_a_seed(call) for call in calls):
        for call in calls:
            decision.report(
                call,
                "GM503",
                "Gymnasium's Env has no seed() (AttributeError) and this class defines none: "
                "seed through the first reset(seed=...) instead",
                FixKind.FLAG,
            )
        return
    for call in calls:
        decision.report(call, "GM503", "self.seed() removed: Gymnasium's Env has no seed() (AttributeError), and gym's seeded nothing this class defines; np_random seeds itself on first use")
    callers = {method.name for call in calls if (method := method_of(decision, call)) is not None}
    decision.plan.seed = SeedPlan(callers=callers, base_calls_only=True)


def _binds_in_class_body(classdef: ast.ClassDef, name: str) -> bool:
    return any(
        isinstance(target, ast.Name) and target.id == name
        for statement in classdef.body
        if isinstance(statement, (ast.Assign, ast.AnnAssign))
        for target in (statement.targets if isinstance(statement, ast.Assign) else [statement.target])
    )


def _state_only_seed_builds(statements: list[ast.stmt], init: ast.AST | None) -> set[str]:
    """``self.x`` attributes the statements assign that ``__init__`` never does: state only
    seed() creates (``self.rand = random.Random(seed)``), not a global seeding call."""
    assigned = {
        target.attr
        for statement in statements
        for node in walk(statement)
        if isinstance(node, (ast.Assign, ast.AnnAssign))
        for target in (node.targets if isinstance(node, ast.Assign) else [node.target])
        if isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"
    }
    if init is not None:
        assigned -= {
            node.attr
            for node in walk(init)
            if isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store) and isinstance(node.value, ast.Name) and node.value.id == "self"
        }
    return assigned


def _reseeding(
    decision: ClassDecision, canonical: ast.Assign, calls: list[ast.Call], seed_method: ast.FunctionDef | ast.AsyncFunctionDef, seed_name: str
) -> tuple[str, str] | None:
    """``(seed_name, "self.np_random, _ = seeding.np_random({})")``: the canonical line of
    seed() on the seed a call passes, in the words of this module, where the seeding
    function it calls is a module-level import every caller of seed() still sees (no
    parameter or local of theirs hides it). ``_`` read in a caller (a translation function)
    is not rebound there: the first element is taken instead."""
    facts = decision.family.facts
    func = canonical.value.func  # type: ignore[attr-defined]  # ``is_seeding_np_random``: a call
    root = func
    while isinstance(root, ast.Attribute):
        root = root.value
    if not isinstance(root, ast.Name):
        return None
    bindings = facts.bindings_of(root)
    if not bindings or not all(isinstance(b, ast.alias) and facts.parent(facts.parent(b)) is facts.tree for b in bindings):
        return None
    callers = {f for call in calls if (f := facts.enclosing_function(call)) is not None and f is not seed_method}
    bound = {n.arg for f in callers for n in walk(f) if isinstance(n, ast.arg)} | {
        n.id for f in callers for n in walk(f) if isinstance(n, ast.Name) and not isinstance(n.ctx, ast.Load)
    }
    if root.id in bound:
        return None
    target = canonical.targets[0]
    attribute = target.elts[0] if isinstance(target, (ast.Tuple, ast.List)) else target
    name = f"self.{attribute.attr}"  # type: ignore[attr-defined]  # ``_np_random_seeding``: a self attribute
    seeding = facts.segment(func)
    if "_" in bound or any(isinstance(n, ast.Name) and n.id == "_" for f in callers for n in walk(f)):
        return seed_name, f"{name} = {seeding}({{}})[0]"
    return seed_name, f"{name}, _ = {seeding}({{}})"


def _passes_one_seed(call: ast.Call, parameter: str) -> bool:
    """``self.seed(s)`` or ``self.seed(<parameter>=s)`` with one seed that is not None, the
    calls ``_SelfSeedCallRemover`` reseeds on."""
    if len(call.args) + len(call.keywords) != 1:
        return False
    if call.args:
        value = call.args[0]
        if isinstance(value, ast.Starred):
            return False
    else:
        if call.keywords[0].arg != parameter:
            return False
        value = call.keywords[0].value
    return not (isinstance(value, ast.Constant) and value.value is None)


def _passes_a_seed(call: ast.Call) -> bool:
    """``self.seed(s)``, not ``self.seed()`` or ``self.seed(None)``."""
    argument = call.args[0] if call.args else next((k.value for k in call.keywords if k.arg is not None), None)
    return argument is not None and not (isinstance(argument, ast.Constant) and argument.value is None)


def _needs_the_method(groups: list[list[ast.stmt]], moved: list[int], setup: list[int], seed_names: set[str]) -> bool:
    """Would moving the statements apart break them? Set-up that draws from the seeded
    generator (``self.offset = self.np_random.integers(3)``) must rerun on every new seed,
    and a statement that reads a local of seed() (``self.world = World(rng)`` after
    ``rng, seed = seeding.np_random(seed)``) cannot run without the statement binding it.
    The seed itself is no such local: every name it had becomes reset()'s ``seed``."""
    carried = set(moved) | set(setup)
    local: dict[str, set[int]] = {}
    for index, group in enumerate(groups):
        for statement in group:
            for node in walk(statement):
                if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
                    local.setdefault(node.id, set()).add(index)
    for index in carried:
        together = set(setup) if index in setup else set(moved)
        for statement in groups[index]:
            for node in walk(statement):
                if index in setup and is_self_attribute(node, NP_RANDOM):
                    return True
                if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load) and node.id in local and node.id not in seed_names:
                    binders = local[node.id] - {index}
                    if binders and not binders <= together:
                        return True
    return False


def _without_dead_locals(groups: list[list[ast.stmt]], moved: list[int]) -> list[int]:
    """The moved statements less the dead ones: those that only computed what seed()
    returned (``seed2 = seeding.hash_seed(seed1 + 1)`` for ``return [seed1, seed2]``): the
    return goes with the method, so in reset() they would be dead code (and a removed
    helper's call); and, with or without a return, a local whose value nothing reads and
    whose computation calls only removed seeding helpers (``seed2 = seeding.hash_seed(seed1
    + 1)`` under a commented-out return): moved, it would raise on every seeded reset and
    drops nothing but a value never used."""
    last = groups[-1] if groups else []
    returns = len(last) == 1 and isinstance(last[0], ast.Return)
    dead = []
    for index in moved:
        group = groups[index]
        if not (len(group) == 1 and isinstance(group[0], ast.Assign)):
            continue
        targets = group[0].targets
        if not all(isinstance(t, ast.Name) for t in targets):
            continue
        if not returns and not _only_removed_helper_calls(group[0].value):
            continue
        names = {t.id for t in targets}  # type: ignore[attr-defined]
        read_elsewhere = any(
            isinstance(node, ast.Name) and node.id in names and isinstance(node.ctx, ast.Load)
            for other, statements in enumerate(groups[:-1] if returns else groups)
            if other != index
            for statement in statements
            for node in walk(statement)
        )
        if not read_elsewhere:
            dead.append(index)
    return [index for index in moved if index not in dead]


def _only_removed_helper_calls(value: ast.expr) -> bool:
    """Calls something, and nothing but ``seeding.hash_seed(...)`` and the like: dropping
    it loses no side effect."""
    calls = [node for node in walk(value) if isinstance(node, ast.Call)]
    return bool(calls) and all(_calls_removed_helpers(call.func) for call in calls)


def _setup_fits_init_end(decision: ClassDecision, statements: list[ast.stmt], init: ast.AST | None) -> bool:
    """Set-up of a seed() no method of the class calls (its callers made the env, then
    seeded it) that may run once at the end of ``__init__`` instead: every ``self``
    attribute it reads ``__init__`` assigns, every one it assigns reset() assigns again at
    its top level (so after the first reset nothing differs), it reads no other name than
    module-level ones and builtins, and ``__init__`` has no ``return`` to skip it."""
    reset = decision.method("reset")
    if not isinstance(init, (ast.FunctionDef, ast.AsyncFunctionDef)) or reset is None or not init.body:
        return False
    if init.body[0].lineno == init.lineno or any(isinstance(n, (ast.Return, ast.Yield, ast.YieldFrom)) for n in walk(init)):
        return False  # a one-line body, or one a return may leave early
    stored = {n.attr for n in walk(init) if is_self_attribute(n) and isinstance(n.ctx, ast.Store)}  # type: ignore[attr-defined]
    reset_sets = {
        target.attr  # type: ignore[attr-defined]  # ``is_self_attribute``: an Attribute
        for statement in reset.body
        if isinstance(statement, (ast.Assign, ast.AnnAssign))
        for target in (statement.targets if isinstance(statement, ast.Assign) else [statement.target])
        if is_self_attribute(target)
    }
    facts = decision.family.facts
    for statement in statements:
        if not isinstance(statement, (ast.Assign, ast.AnnAssign, ast.Expr, ast.Assert)):
            return False
        for node in walk(statement):
            if is_self_attribute(node):
                if isinstance(node.ctx, ast.Store) and node.attr not in reset_sets:  # type: ignore[attr-defined]
                    return False
                if isinstance(node.ctx, ast.Load) and node.attr not in stored:  # type: ignore[attr-defined]
                    return False
            elif isinstance(node, ast.Name) and node.id != "self":
                bindings = facts.bindings_of(node)
                if isinstance(node.ctx, ast.Store) or any(facts.enclosing_function(b) is not None for b in bindings):
                    return False
    return True


def _calls_removed_helpers(function: ast.AST) -> bool:
    """``seeding.hash_seed(...)`` and the like (GM506): calling this seed() would fail."""
    return any(
        isinstance(node, ast.Attribute) and node.attr in REMOVED_SEEDING_HELPERS and full_name(node.value) == "seeding"
        for node in walk(function)
    )


def _keep_as_helper(decision: ClassDecision, seed_method: ast.FunctionDef | ast.AsyncFunctionDef, why: str) -> None:
    """seed() stays as it is (``seeding.np_random`` still exists) and reset() calls it with
    the seed it is given, as ``env.seed(s); env.reset()`` did."""
    reset = decision.method("reset")
    if reset is None:
        decision.report(seed_method, "GM503", "seed() does more than seed np_random and this class has no reset(); call it from reset() under `if seed is not None:`", FixKind.FLAG, question=moving_seed_question(seed_method))
        return
    if _reset_calls_seed(decision, seed_method):
        return  # reset() calls it already (migrated)
    decision.plan.seed = SeedPlan(keep=True)
    decision.report(
        seed_method,
        "GM503",
        f"seed() kept as a helper: {why}; reset() now calls it when given a seed, as `env.seed(s)` before reset() did",
        FixKind.ASSIST,
        # the rewrite keeps what `env.seed(s); env.reset()` did, nothing is left to decide
        Tier.NOTE,
    )


def _reset_calls_seed(decision: ClassDecision, seed_method: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    reset = decision.method("reset")
    return reset is not None and any(
        isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == seed_method.name
        and isinstance(node.func.value, ast.Name) and node.func.value.id == "self"
        for node in walk(reset)
    )


def _untraced_seed_call(decision: ClassDecision) -> ast.Call | None:
    """An ``x.seed(...)`` elsewhere in the file that the seed rules leave in place because
    ``x`` may or may not be a Gym env: if it is an instance of this class, removing
    ``seed()`` would turn that call into an AttributeError."""
    family = decision.family
    for call in family.facts.attribute_calls.get("seed", ()):
        receiver = call.func.value  # type: ignore[attr-defined]
        if is_space(receiver):
            continue
        on_self = isinstance(receiver, ast.Name) and receiver.id == "self"
        on_super = is_super_call(receiver)
        if on_self or on_super:
            # `self.seed(7)` in a subclass that inherits this seed(): it would lose it.
            # (A subclass's own seed() is decided with that subclass.)
            caller = family.facts.enclosing_class(call)
            if caller is not None and caller is not decision.classdef and _inherits_seed(decision, caller):
                function = family.facts.enclosing_function(call)
                if function is None or function.name != "seed":
                    return call
            continue
        verdict = decide(family.receivers.kind_of(receiver), receiver, family.context.profile)
        if verdict.action is Action.REPORT:
            return call
    return None


def _called_below_elsewhere(decision: ClassDecision, seed_method: ast.FunctionDef | ast.AsyncFunctionDef) -> list[str]:
    """The subclasses in other modules of the run whose ``self.seed(...)`` (or
    ``super().seed(...)``) reaches this seed(), by its name or as the ``_seed`` gym <= 0.9's
    ``Env.seed`` called: ``Class (module.py)``."""
    project = decision.family.receivers.project
    if project is None or decision.family.facts.parent(decision.classdef) is not decision.family.facts.tree:
        return []
    names = {seed_method.name, "seed"}
    found = sorted({where for name in names for where in project.called_below_elsewhere(decision.classdef.name, name)})
    return [f"`{where.rsplit(':', 1)[1]}` ({os.path.basename(where.rsplit(':', 1)[0])})" for where in found]


def _seed_called_in_run(decision: ClassDecision) -> bool:
    """This module or another of the run calls ``x.seed(...)`` / ``x._seed(...)`` on what may
    be an env (not ``np.random`` nor a space): the seed() may have run before."""
    project = decision.family.receivers.project
    return calls_seed(decision.family.facts) or (project is not None and project.seed_used())


def _seed_called_without_a_value(decision: ClassDecision, calls: list[ast.Call], seed_method: ast.AST) -> bool:
    """A call of seed() the run sees passes no seed: ``self.seed()`` in the class (its
    constructor's included), or an ``x.seed()`` / ``x.seed(None)`` in this module or another
    of the run (``calls_seed_without_a_value``); the extra seeding ran there too."""
    facts = decision.family.facts
    if any(facts.enclosing_function(call) is not seed_method and not passes_a_value(call) for call in calls):
        return True
    project = decision.family.receivers.project
    return calls_seed_without_a_value(facts) or (project is not None and project.seed_used_without_a_value())


def _inherits_seed(decision: ClassDecision, classdef: ast.ClassDef) -> bool:
    """``classdef`` derives from the decided class through local classes, none of which
    (``classdef`` included) defines its own seed() in between."""
    lineage = decision.family.receivers.local_lineage(classdef, follows=lambda current: not _defines_seed(current))
    return any(current is decision.classdef for current in lineage)


def _defines_seed(classdef: ast.ClassDef) -> bool:
    return any(isinstance(s, (ast.FunctionDef, ast.AsyncFunctionDef)) and s.name in ("seed", "_seed") for s in classdef.body)


def _seed_call_sites(decision: ClassDecision) -> list[ast.Call]:
    names = {"seed", decision.renamed.get("seed", "seed")}
    calls = [call for name in sorted(names) for call in decision.index.self_calls.get(name, ())]
    if decision.plan.dropped:  # the forwarding ``seed`` that goes is no caller
        calls = [c for c in calls if (m := method_of(decision, c)) is None or m.name not in decision.plan.dropped]
    calls.sort(key=lambda c: (c.lineno, c.col_offset))
    return calls


def _np_random_seeding(decision: ClassDecision, group: list[ast.stmt]) -> set[str] | None:
    """``self.np_random, seed = seeding.np_random(seed)``: the names bound besides np_random."""
    if len(group) != 1 or not isinstance(group[0], ast.Assign):
        return None
    assign = group[0]
    if len(assign.targets) != 1 or not decision.env.is_seeding_np_random(assign.value):
        return None
    target = assign.targets[0]
    if is_self_attribute(target, NP_RANDOM):
        return set()
    if isinstance(target, (ast.Tuple, ast.List)) and target.elts and is_self_attribute(target.elts[0], NP_RANDOM):
        return {e.id for e in target.elts[1:] if isinstance(e, ast.Name)}
    return None


def _is_seeding_statement(group: list[ast.stmt], seed_names: set[str]) -> bool:
    """Uses the seed, or seeds something (``random.seed()``, ``space.seed()``, ``sim.set_seed()``)."""
    for statement in group:
        if seed_names & set(identifiers(statement)):
            return True
        for node in walk(statement):
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and "seed" in node.func.attr:
                return True
    return False


def _only_prints(facts: ModuleFacts, group: list[ast.stmt]) -> bool:
    """Every statement is a call of the builtin ``print`` or of the ``logging`` module (or
    gym's ``logger``) as a statement: output only, no state."""
    for statement in group:
        if not (isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Call)):
            return False
        func = statement.value.func
        if isinstance(func, ast.Name) and func.id == "print" and not facts.bindings_of(func):
            continue
        names = facts.qualified_names(func)
        if not names or not all(name.startswith(("logging.", "gym.logger.", "gymnasium.logger.")) for name in names):
            return False
    return True


def _seeds_held_object(statement: ast.Return) -> bool:
    """``return self.scene.seed(seed)``: the value calls a method of an object the class
    holds (``self.<attribute>.<method>(...)``), seeding work of its own, not a ``[seed]``
    that only reports what was done."""
    return any(
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and is_self_attribute(node.func.value)
        for node in walk(statement)
    )


def _does_nothing(group: list[ast.stmt]) -> bool:
    """``pass`` or ``...``: a body that seeds nothing."""
    return len(group) == 1 and (
        isinstance(group[0], ast.Pass)
        or (isinstance(group[0], ast.Expr) and isinstance(group[0].value, ast.Constant) and group[0].value.value is Ellipsis)
    )
