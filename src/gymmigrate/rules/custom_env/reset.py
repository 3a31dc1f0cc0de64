"""GM501 / GM502: ``reset`` takes ``seed`` and ``options`` and returns ``(obs, info)``.

Gymnasium's wrappers (``TimeLimit`` from ``make`` included) always call
``env.reset(seed=..., options=...)``, and ``Env.reset`` is what seeds ``self.np_random``,
so ``super().reset(seed=seed)`` goes first. gym 0.22-0.25's ``return_info`` flag is gone
in 0.26: its ``(obs, info)`` branch is the only one left (GM502). A ``self.reset()`` the
class calls itself now returns a pair too.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.env_classes import (
    env_base_call,
    is_self_attribute,
    is_super_method_call,
)
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import own_returns, walk
from gymmigrate.facts.own_api import is_info_pair
from gymmigrate.facts.own_steps import self_step_gives_five
from gymmigrate.facts.receiver_classes import is_object
from gymmigrate.facts.rng_handovers import reads_np_random
from gymmigrate.facts.summaries.untraced import passes_return_info
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.custom_env.common import (
    ClassDecision,
    Method,
    callable_without_arguments,
    delegates,
    inner_gym_env_call,
    is_self_call,
    method_of,
    param_names,
    random_state_np_random,
)
from gymmigrate.rules.custom_env.hooks import overrides
from gymmigrate.rules.env_ids.syntax import gym_alias
from gymmigrate.rules.reset_seed.contract import blocked_params, run_contract


def decide_reset(decision: ClassDecision) -> None:
    function = decision.method("reset")
    if function is None:
        return
    names = param_names(function)
    legacy_flag = "return_info" in names
    modern = "seed" in names and "options" in names and not legacy_flag
    # ``def reset(self, **kwargs): obs = super().reset(**kwargs)`` (or an inner Gym env's
    # ``self.env.reset(**kwargs)``): seed and options already reach that reset through
    # ``**kwargs``; new keyword-only parameters would take them.
    forwards = not modern and not legacy_flag and _forwards_keywords(decision, function)
    decision.plan.reset_forwards_keywords = forwards
    bases = reset_bases(decision)
    super_resets = any(is_base_reset(c, bases) for s in function.body for c in walk(s) if isinstance(c, ast.Call))
    # The base reset the call reaches is one the run keeps as it was (a helper of the
    # project's own API, beside a step it keeps): it takes no seed and returns what it did,
    # so the call stays as it is, and np_random is seeded by Env.reset(self, seed=seed).
    base_kept = super_resets and decision.family.receivers.inherited_reset_kept(decision.classdef)
    decision.plan.reset_base_kept = base_kept
    if legacy_flag:
        # A flag the body never reads (gym 0.22-0.25 signatures often took it unused) had
        # one mode only: dropping it and returning the pair is the whole migration, a note.
        # Handed on only as ``return_info=`` to an inner ``reset()`` (dropped there too): the
        # inner env had the modes, and its Gymnasium reset returns the pair; nothing is left
        # to decide here either.
        read = _reads_name(function, "return_info", skip=_handed_to_reset(function))
        handed = not read and _reads_name(function, "return_info")
        # A body that chose between modes: the bare-observation mode is gone, which only a
        # caller passing a mode (``reset(return_info=False)``) can have relied on. With none
        # in the run, every caller got the default, and the caller rules migrate those.
        chosen = read and _return_info_passed(decision)
        decision.report(
            function,
            "GM502",
            "return_info removed: reset() always returns (obs, info) now; check callers that expected a bare observation"
            if chosen
            else "return_info removed (no caller in the run passes it; the callers' unpacking is migrated with them): "
            "reset() always returns (obs, info) now"
            if read
            else "return_info removed (reset() only handed it on to an inner reset(), which returns (obs, info) in "
            "Gymnasium): reset() returns (obs, info) now"
            if handed
            else "return_info removed (reset() never read it): reset() returns (obs, info) now",
            tier=None if chosen else Tier.NOTE,
        )
        for ret in untested_returns(function):
            decision.plan.reset_pairs_untested = True
            if read:
                decision.report(
                    ret,
                    "GM502",
                    "this return tests no return_info (another mode of the env): it returns (obs, {}) now like the others, "
                    "so every caller of reset(), migrated to unpack (obs, info), gets the pair in either mode",
                    FixKind.ASSIST,
                )
            else:
                decision.report(ret, "GM502", "reset returns (obs, {})", FixKind.ASSIST, Tier.NOTE)
    elif not modern and _returns_pairs(function):
        # gym 0.26: ``def reset(self, seed=None): ... return obs, {}``: already the pair.
        decision.plan.reset_returns_pairs = True
    elif not modern:
        base_info = None if base_kept else _unpack_super_reset(decision, function)
        # ``def reset(self): return self._reset()`` gets ``(self._reset(), {})``; only a
        # helper that itself returns a reset's result (``return self.env.reset()``, a pair
        # now) returns the pair instead, when reset is its only caller. A hook subclasses
        # override is not followed either: `(self._restart(), {})` is right for each.
        helpers = [
            h for h in delegates(decision, function) if overrides(decision, h.name) == ([], []) and _returns_a_reset(decision, h)
        ]
        decision.plan.reset_helpers = [h.name for h in helpers]
        _return_info_pairs(decision, function, base_info, set(decision.plan.reset_helpers))
        for helper in helpers:
            _return_info_pairs(decision, helper, None, set())
    decision.plan.reset_bases = bases
    # Only an inner env's reset gets the keywords: that env seeds itself, and this class
    # has no ``seed`` name of its own to seed np_random with.
    inner_only = forwards and not super_resets
    decision.plan.reset_super_seeds = not inner_only and not base_kept and decision.env.extends_gym_env_directly(decision.classdef)
    inserted = False
    random_state = random_state_np_random(decision)
    kept_random_state = random_state is not None and not super_resets and decision.plan.reset_super_seeds
    if kept_random_state:
        # ``self.np_random = np.random.RandomState()`` seeded by the class's own seed():
        # Env.reset(seed=s) would replace it by a Generator, and the RandomState calls
        # (``self.np_random.seed(s)``, ``randint``) would raise. Left unseeded by the base,
        # the class seeds as it did; moving to Env's Generator is a change of every draw.
        decision.plan.reset_super_seeds = False
        if not modern:  # a reset already written for gym 0.26 / Gymnasium chose this itself
            decision.report(
                function,
                "GM501",
                f"reset() does not call super().reset(seed=seed): np_random is the class's own RandomState (line {random_state.lineno}), "  # type: ignore[union-attr]
                "which Env.reset would replace by a Generator its RandomState calls fail on; it keeps seeding as before. "
                "To use Gymnasium's seeding, drop the RandomState (and seed()), call super().reset(seed=seed) and use the "
                "Generator methods (randint -> integers)",
                FixKind.FLAG,
            )
    seeding_super = super_resets and not base_kept
    hook = None if kept_random_state or inner_only or decision.plan.reset_super_seeds or seeding_super else private_reset_seed_hook(decision, function)
    hooked = hook if not modern else None
    if kept_random_state or inner_only:
        pass
    elif decision.plan.reset_super_seeds or seeding_super:
        inserted = not super_resets
    elif hooked:
        # the base's reset would reset a second time; its seed hook is what legacy
        # ``env.seed(n)`` ran before this reset
        decision.plan.reset_seed_hook = hooked
        decision.report(function, "GM501", f"reset calls the base's private reset hook, not its reset: it seeds through the base's `{hooked}` when given a seed, as legacy seed(seed) did")
    elif hook is not None and any(is_self_call(c, {hook}) for c in decision.function(function).of(ast.Call)):
        pass  # seeds through the base's hook already (as this rule writes it)
    elif any(_seeds_through_env_reset(decision, c, function) for c in decision.function(function).of(ast.Call)):
        pass  # seeds through Env's own reset already (as this rule writes it)
    elif not reads_np_random(decision.family.facts):
        # Nothing of the module draws from np_random (a batch seeds its envs inside, say; a
        # seed() that only stores one): leaving it unseeded changes nothing here, so this is
        # not a decision.
        decision.report(
            function,
            "GM501",
            f"reset() does not seed np_random ({_unseeded_why(base_kept)}); "
            "nothing in this module reads np_random, so nothing draws from it unseeded",
            FixKind.FLAG,
            Tier.NOTE,
        )
    elif (own := _own_class_reset(decision, function)) is not None:
        # ``Nav.reset(self)`` inside Nav's own reset (legacy recursion, meant as the base's
        # reset): the body already runs a reset of the hierarchy, and the base's seeds once
        # it is given the seed; Env.reset by hand beside it would be the wrong advice.
        decision.report(
            function,
            "GM501",
            f"reset() calls `{own}.reset(self)`, its own class's reset (a base's reset where it is meant): that reset "
            "seeds np_random once it is given `seed=seed`; where the call is fixed, pass the seed there",
            FixKind.FLAG,
            Tier.NOTE,
        )
    elif not modern and (gymnasium := _env_reset_seeds(decision)) is not None:
        # Gymnasium's Env.reset only seeds np_random (when given a seed): called as a plain
        # function on an instance of a class that derives from Env, it is exactly the
        # seeding super().reset(seed=seed) would have done, without the base's own reset
        decision.plan.reset_env_seeds = gymnasium
        inserted = True
        decision.report(
            function,
            "GM501",
            f"reset() must seed np_random, but {_unseeded_why(base_kept)}: it calls "
            f"`{gymnasium}.Env.reset(self, seed=seed)` first, which seeds np_random as Gymnasium's Env.reset does and nothing else",
            tier=Tier.NOTE,
        )
    else:
        decision.report(
            function,
            "GM501",
            f"reset() must seed np_random, but {_unseeded_why(base_kept)}; call Env.reset(self, seed=seed) first by hand",
            FixKind.FLAG,
        )
    if inserted and not modern:
        _handed_np_random(decision, function)
    migrates = not modern and not (forwards and decision.plan.reset_returns_pairs)
    methods = decision.methods
    if not modern and not inner_only and decision.plan.published and "_seed" in methods and "seed" not in methods:
        # ``seed = _seed`` beside a public legacy reset: the hook keeps its name, and
        # reset(seed=n) runs it as legacy ``seed(n)`` did (it may seed more than np_random)
        hooked = "_seed"
        decision.plan.reset_seed_hook = hooked
        decision.report(function, "GM501", "reset seeds through the class's `_seed` hook when given a seed, as legacy seed(seed) did")
    decision.plan.reset = (
        migrates
        or inserted
        or bool(hooked)
        or decision.plan.seed is not None and (bool(decision.plan.seed.moved) or decision.plan.seed.keep)
        or (not base_kept and any(_super_reset_needs_seed(c, bases) for s in function.body for c in walk(s)))
    )
    if forwards and migrates:
        where = "the inner env's reset()" if inner_only else "super().reset()"
        decision.report(function, "GM501", f"reset passes seed and options on to {where} in its **kwargs (wrappers always pass them)")
    elif migrates or inserted:
        star_kwarg = function.args.kwarg.arg if function.args.kwarg else None
        extra = [n for n in names[1:] if n not in ("seed", "options", "return_info", star_kwarg)]
        if extra and not legacy_flag and not _all_defaulted(function, extra):
            kept = f"reset keeps its own parameters ({', '.join(extra)}) before seed/options"
            receivers = decision.family.receivers
            if receivers.class_kind(decision.classdef) is EnvKind.GYM_ENV and blocked_params(run_contract(decision.family.facts, receivers), function):
                # The run passes some of them down its wrappers and GM207 asks at this same
                # reset whether they move into options: one decision, one item.
                decision.report(function, "GM501", f"{kept}; whether they move into options is the GM207 item on this reset", FixKind.ASSIST, Tier.NOTE)
            else:
                decision.report(function, "GM501", f"{kept}; Gymnasium code passes such settings in options", FixKind.ASSIST)
        elif extra and not legacy_flag:
            # Every one has a default: Gymnasium's callers (keyword seed/options only) and the
            # project's own positional calls both work as they are, nothing to decide.
            decision.report(
                function,
                "GM501",
                f"reset takes seed and options (wrappers always pass them) after its own defaulted parameters ({', '.join(extra)})",
            )
        elif not legacy_flag:
            # Env.reset called by name has a note of its own
            seeds = ", and calls super().reset(seed=seed) first to seed np_random" if inserted and not decision.plan.reset_env_seeds else ""
            decision.report(function, "GM501", f"reset takes seed and options (wrappers always pass them){seeds}")


def _unseeded_why(base_kept: bool) -> str:
    """Why the reset cannot seed through its base's reset."""
    if base_kept:
        return "the base's reset it calls stays as it was in this run, without seed/options (its class keeps its own API), and is called as before"
    return "super().reset() here would also run the base env's own reset"


def _seeds_through_env_reset(decision: ClassDecision, call: ast.AST, function: ast.AST) -> bool:
    """``gymnasium.Env.reset(self, seed=seed)``: Env's own reset given the seed."""
    return env_base_call(decision.family.facts, call, "reset", function) and any(
        k.arg == "seed" for k in call.keywords  # type: ignore[attr-defined]
    )


def _env_reset_seeds(decision: ClassDecision) -> str | None:
    """The name the migrated module calls Gymnasium by (adding ``import gymnasium`` where it
    has none), when the class is known to derive from ``Env`` through its bases (this
    module's, the run's or Gymnasium's own: a Gym env class with a base, not a plain class
    that forwards to an env), so ``Env.reset(self, seed=seed)`` seeds its np_random; None
    otherwise, and where the class seeds through a ``seed()`` of its own that moves into reset."""
    classdef = decision.classdef
    if decision.family.receivers.class_kind(classdef) is not EnvKind.GYM_ENV:
        return None
    if not any(not is_object(base) for base in classdef.bases) or decision.plan.seed is not None:
        return None
    return gym_alias(decision.family.facts) or decision.family.plan.ensure_import("gymnasium")


def _handed_np_random(decision: ClassDecision, reset: ast.AST) -> None:
    """``self.scene.np_random = self.np_random``: the class hands its generator to another
    object once. The ``super().reset(seed=seed)`` the migrated reset calls first replaces
    ``self.np_random`` by a new Generator whenever it is given a seed, and that object keeps
    drawing from the old one, so a seeded reset no longer reseeds what it draws. Handed in
    ``__init__`` to ``self.<attr>``, an object set once before it and never rebound, the same
    object is there in every reset: reset hands it the new generator again. Anywhere else
    (a local built in a helper, an attribute that may be None or rebound) which object
    reset would reach is not known: reported."""
    seed_method = decision.method("seed")
    kept_seed = seed_method if decision.plan.seed is not None and decision.plan.seed.keep else None
    init = decision.methods.get("__init__")
    facts = decision.family.facts
    for node in walk(decision.classdef):
        if not (isinstance(node, ast.Assign) and len(node.targets) == 1 and is_self_attribute(node.value, NP_RANDOM_NAMES)):
            continue
        target = node.targets[0]
        if not isinstance(target, ast.Attribute) or target.attr not in NP_RANDOM_NAMES or is_self_attribute(target):
            continue
        function = facts.enclosing_function(node)
        if function is reset and node in reset.body:
            continue  # reset hands it on itself, after the seeding
        if reset is not None and _runs_every_reset(decision, reset, function, node):
            continue  # a helper every reset calls builds the object and hands it on, after the seeding
        if kept_seed is not None and function is kept_seed:
            continue  # the kept seed() reset calls with the seed hands it on again
        if function is init and init is not None and _set_once_before(decision, init, node, target.value):
            decision.plan.reset_rehands.append(facts.segment(node))
            decision.report(
                node,
                "GM501",
                f"reset(seed=...) replaces self.np_random; reset now hands the new generator to "
                f"`{facts.segment(target.value)}` again after super().reset(seed=seed), as this line did once",
                FixKind.ASSIST,
                Tier.NOTE,
            )
            continue
        decision.report(
            node,
            "GM501",
            f"`{facts.segment(node)}` hands this env's generator to another object once; reset(seed=...) now replaces "
            "self.np_random (super().reset(seed=seed)) and that object keeps drawing from the old one, so a seeded "
            "reset does not reseed it: hand it the new generator in reset() after super().reset(seed=seed)",
            FixKind.FLAG,
        )


def _runs_every_reset(decision: ClassDecision, reset: ast.AST, helper: ast.AST | None, statement: ast.stmt) -> bool:
    """``statement`` is a top-level statement of a method of the class that reset calls as
    ``self.<method>(...)`` in one of its own top-level, simple statements: every reset runs
    it, after the seeding the migrated reset does first. A call under a condition (``if
    self.scene is None:``, a lazy build) is not every reset."""
    if not isinstance(helper, (ast.FunctionDef, ast.AsyncFunctionDef)) or statement not in helper.body:
        return False
    if decision.methods.get(helper.name) is not helper:
        return False
    compound = (ast.If, ast.For, ast.AsyncFor, ast.While, ast.With, ast.AsyncWith, ast.Try, ast.FunctionDef, ast.ClassDef)
    for top in getattr(reset, "body", []):
        if isinstance(top, compound):
            continue
        for node in ast.walk(top):
            if isinstance(node, ast.Call) and is_self_attribute(node.func, (helper.name,)):
                return True
    return False


NP_RANDOM_NAMES = ("np_random", "_np_random")


def _set_once_before(decision: ClassDecision, init: ast.AST, handoff: ast.stmt, receiver: ast.expr) -> bool:
    """``receiver`` is ``self.<attr>``, assigned by a statement of ``__init__``'s own body
    before ``handoff`` (itself one of that body's statements), and nowhere else in the class:
    every later reset finds that same object there."""
    if not is_self_attribute(receiver):
        return False
    body = init.body  # type: ignore[attr-defined]
    if handoff not in body:
        return False
    name = receiver.attr  # type: ignore[attr-defined]
    stores = [
        node
        for node in walk(decision.classdef)
        if is_self_attribute(node, (name,)) and isinstance(node.ctx, (ast.Store, ast.Del))  # type: ignore[attr-defined]
    ]
    if len(stores) != 1:
        return False
    before = body[: body.index(handoff)]
    return any(
        isinstance(statement, ast.Assign) and len(statement.targets) == 1 and statement.targets[0] is stores[0]
        for statement in before
    )


def _return_info_passed(decision: ClassDecision) -> bool:
    """Some caller of the run (this module alone when it is run alone) passes a reset a
    ``return_info`` mode (``summaries.untraced.passes_return_info``)."""
    project = decision.family.receivers.project
    return passes_return_info(decision.family.facts) or (project is not None and project.return_info_passed())


def _reads_name(function: ast.AST, name: str, skip: frozenset[int] = frozenset()) -> bool:
    return any(
        isinstance(node, ast.Name) and node.id == name and isinstance(node.ctx, ast.Load) and id(node) not in skip
        for node in walk(function)
    )


def _handed_to_reset(function: ast.AST) -> frozenset[int]:
    """The ``return_info`` names passed as ``return_info=return_info`` to a ``.reset(...)``
    call in ``function`` (the rewrite drops that keyword)."""
    return frozenset(
        id(keyword.value)
        for node in walk(function)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "reset"
        for keyword in node.keywords
        if keyword.arg == "return_info" and isinstance(keyword.value, ast.Name) and keyword.value.id == "return_info"
    )


def _all_defaulted(function: ast.AST, names: list[str]) -> bool:
    """Each of ``names`` (parameters of ``function``) has a default value."""
    args = function.args  # type: ignore[attr-defined]
    positional = [*args.posonlyargs, *args.args]
    defaulted = {a.arg for a in positional[len(positional) - len(args.defaults) :]} if args.defaults else set()
    defaulted |= {a.arg for a, d in zip(args.kwonlyargs, args.kw_defaults) if d is not None}
    return all(name in defaulted for name in names)


def untested_returns(function: ast.AST) -> list[ast.Return]:
    """Returns of a legacy ``reset(..., return_info=False)`` outside every ``if return_info``
    / ``if not return_info`` (and ``... if return_info else ...``) that give one value: the
    legacy reset returned it bare even when asked for the info (a mode the flag never
    reached). ``cst_edits.pair_untested_returns`` pairs the same returns."""
    found: list[ast.Return] = []

    def visit(statements: list[ast.stmt]) -> None:
        for statement in statements:
            if isinstance(statement, ast.If) and _tests_return_info(statement.test):
                break  # what follows in this block is one of the flag's two paths
            if isinstance(statement, ast.Return):
                value = statement.value
                if value is None or isinstance(value, (ast.Tuple, ast.IfExp)) or (isinstance(value, ast.Constant) and value.value is None):
                    continue
                if isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr in ("reset", "_reset"):
                    continue  # a base's or a held env's reset: the pair comes from there
                found.append(statement)
            elif isinstance(statement, _BLOCKS):
                for field in ("body", "orelse", "finalbody"):
                    visit(getattr(statement, field, []))
                for handler in getattr(statement, "handlers", []):
                    visit(handler.body)

    visit(function.body)  # type: ignore[attr-defined]
    return found


_BLOCKS = (ast.If, ast.For, ast.AsyncFor, ast.While, ast.With, ast.AsyncWith, ast.Try)


def _tests_return_info(test: ast.expr) -> bool:
    if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
        test = test.operand
    return isinstance(test, ast.Name) and test.id == "return_info"


def _forwards_keywords(decision: ClassDecision, function: ast.AST) -> bool:
    """``reset(self, ..., **kwargs)`` whose every ``super().reset(...)`` (and inner Gym env
    ``reset``) passes ``**kwargs`` on."""
    kwarg = function.args.kwarg.arg if function.args.kwarg else None  # type: ignore[attr-defined]
    if kwarg is None:
        return False
    calls = [
        c
        for s in function.body  # type: ignore[attr-defined]
        for c in walk(s)
        if isinstance(c, ast.Call) and (is_base_reset(c, reset_bases(decision)) or inner_gym_env_call(decision, c, "reset"))
    ]
    return bool(calls) and all(
        any(k.arg is None and isinstance(k.value, ast.Name) and k.value.id == kwarg for k in call.keywords) for call in calls
    )


def _returns_pairs(function: ast.AST) -> bool:
    """Every ``return`` of ``function`` gives ``(obs, info)`` already: a two-element tuple
    whose second element is a dict (a display, ``dict(...)``) or named like an info."""
    returns = [ret for ret in own_returns(function) if ret.value is not None]
    return bool(returns) and all(is_info_pair(ret.value) for ret in returns)  # type: ignore[arg-type]


def _unpack_super_reset(decision: ClassDecision, function: ast.AST) -> str | None:
    facts = decision.family.facts
    index = decision.function(function)
    info_name: str | None = None
    for call in index.of(ast.Call):
        if not is_base_reset(call, reset_bases(decision)):
            continue
        parent = facts.parent(call)
        if isinstance(parent, ast.Assign) and len(parent.targets) == 1 and isinstance(parent.targets[0], ast.Name) and info_name is None:
            info_name = "info" if "info" not in index.names else "base_info"
            decision.report(
                call,
                "GM501",
                f"{_spelled(call)} returns (obs, info) now: unpacked, and reset returns that {info_name}",
                FixKind.ASSIST,
                # a base of Gym's own returns the pair in Gymnasium: nothing to decide
                Tier.NOTE if decision.env.builtin_env_base(decision.classdef) else None,
            )
        elif not isinstance(parent, (ast.Expr, ast.Return)):
            decision.report(call, "GM501", f"{_spelled(call)} returns (obs, info) now: unpack it where its result is used", FixKind.FLAG)
    return info_name


def _returns_a_reset(decision: ClassDecision, helper: ast.AST) -> bool:
    """A return of ``helper`` is some reset's result (the base's, an inner env's, a retry
    of this one): a pair in Gymnasium, which ``(self.helper(), {})`` would nest."""
    retries = {"reset", decision.renamed.get("reset", "reset")}
    return any(
        is_base_reset(ret.value, reset_bases(decision)) or is_self_call(ret.value, retries) or inner_gym_env_call(decision, ret.value, "reset")
        for ret in own_returns(helper)
        if ret.value is not None
    )


def _return_info_pairs(decision: ClassDecision, function: ast.AST, base_info: str | None, helpers: set[str]) -> None:
    kind = FixKind.AUTO
    why = "returns (obs, {})"
    known_dict = False
    if base_info is not None:
        kind, why = FixKind.ASSIST, f"returns (obs, {base_info}) with the info of the base's reset"
    elif decision.function(function).assigns_name("info"):
        kind, why = FixKind.ASSIST, "returns (obs, info) with the info dict reset() already builds"
        # where every value ``info`` takes is a dict the class writes itself, nothing is asked
        known_dict = _info_is_own_dict(decision, function)
    elif "_get_info" in decision.methods:
        # Only a helper that takes no arguments can be called here: `_get_info(self, agent)`
        # called as `self._get_info()` would raise TypeError on the first reset.
        if callable_without_arguments(decision.methods["_get_info"]):
            decision.plan.info_helper = True
            kind, why = FixKind.ASSIST, "returns (obs, self._get_info()), the info the class already builds"
        else:
            why = "returns (obs, {}): _get_info() needs arguments reset() does not have, so it is not called"
    retries = {"reset", decision.renamed.get("reset", "reset")}  # ``return self.reset()``: the retry's pair
    for ret in own_returns(function):
        if ret.value is None or is_base_reset(ret.value, reset_bases(decision)) or is_self_call(ret.value, helpers | retries):
            continue
        if inner_gym_env_call(decision, ret.value, "reset"):
            # ``return self.env.reset()``: the inner env's reset returns (obs, info) now and
            # the reset rule (GM201) passes it through; adding ``{}`` would nest the pair.
            decision.plan.inner_reset_receivers.add(decision.family.facts.segment(ret.value.func.value))  # type: ignore[attr-defined]
            if not ret.value.args and not ret.value.keywords:  # type: ignore[attr-defined]
                held = decision.family.facts.segment(ret.value.func.value)  # type: ignore[attr-defined]
                decision.report(ret, "GM501", f"reset returns {held}.reset(), (obs, info) in Gymnasium: passed seed and options")
            continue
        tier = Tier.NOTE if (base_info is not None and decision.env.builtin_env_base(decision.classdef)) or known_dict else None
        # every return of one reset answers the same question (is that info what reset should give?)
        decision.report(ret, "GM501", f"reset {why}", kind, tier, question=("reset-info", id(function)) if kind is FixKind.ASSIST else None)


def _info_is_own_dict(decision: ClassDecision, function: ast.AST) -> bool:
    """Every binding of ``info`` in ``function`` is a dict display, or the last of the
    names unpacked from a call of the class's own method whose every return is a tuple
    ending in a dict display (``obs, reward, done, info = self.observe()``)."""
    bindings = [node for node in walk(function) if isinstance(node, ast.Name) and node.id == "info" and isinstance(node.ctx, ast.Store)]
    if not bindings:
        return False
    facts = decision.family.facts
    for name in bindings:
        parent = facts.parent(name)
        if isinstance(parent, ast.Assign) and parent.targets == [name]:
            if not isinstance(parent.value, ast.Dict):
                return False
            continue
        if not (isinstance(parent, ast.Tuple) and parent.elts and parent.elts[-1] is name):
            return False
        statement = facts.parent(parent)
        if not (isinstance(statement, ast.Assign) and statement.targets == [parent] and isinstance(statement.value, ast.Call)):
            return False
        func = statement.value.func
        if not (isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) and func.value.id == "self"):
            return False
        method = decision.methods.get(func.attr)
        returns = own_returns(method) if method is not None else []
        if not returns or not all(
            isinstance(ret.value, ast.Tuple) and len(ret.value.elts) == len(parent.elts) and isinstance(ret.value.elts[-1], ast.Dict)
            for ret in returns
        ):
            return False
    return True


def decide_internal_calls(decision: ClassDecision) -> None:
    """``obs = self.reset()`` in the class itself: reset() returns (obs, info) now. So does
    the base's reset that ``obs = super().reset()`` (or ``Base.reset(self)``) calls outside
    the class's own reset, a helper's (``_reset`` beside a public ``reset``)."""
    facts = decision.family.facts
    unpackable = False
    own_reset = decision.method("reset")
    bases = reset_bases(decision)
    for target, code in (("reset", "GM501"), ("step", "GM504")):
        # ``self._step(a)`` is the step only where the gym < 0.9 name is renamed; beside a
        # ``step`` of the class (or of a base of the run) it is a hook on a contract of its own
        legacy = ("_" + target,) if decision.renamed.get(target) == "_" + target else ()
        up = _base_resets_outside_reset(decision, own_reset, bases) if target == "reset" else []
        for call in (*decision.index.self_calls.get(target, ()), *(c for name in legacy for c in decision.index.self_calls.get(name, ())), *up):
            method = method_of(decision, call)
            # a reset's own ``self.reset()`` is its recursion; its ``self.step()`` (a warm-up) is
            # a caller like any other, asked about where the steps it may run do not all give five
            if method is None or method.name in decision.removed or (target == "reset" and (method.name == "reset" or method is own_reset)):
                continue
            parent = facts.parent(call)
            if isinstance(parent, ast.Expr):
                continue
            if isinstance(parent, ast.Return) and is_self_call(call, set(decision.plan.step_helpers if target == "step" else decision.plan.reset_helpers)):
                continue  # a delegation the rewrite followed: the helper returns the new contract
            if target == "step" and call.func.attr == "step" and self_step_gives_five(facts, decision.family.receivers, decision.classdef, method.name):
                continue  # every step it may run gives five values: the step family moves this call with them
            if call in up:
                decision.plan.reset_bases = bases  # the build unpacks ``Base.reset(self)`` as well
            if (
                target == "reset"
                and isinstance(parent, ast.Assign)
                and len(parent.targets) == 1
                and isinstance(parent.targets[0], (ast.Name, ast.Attribute))
                and parent.value is call
            ):
                unpackable = True
                decision.plan.reset_callers.add(method.name)
                # The class's own reset is rebuilt to return the pair, so the unpack is made
                # and certain: a note naming the target the code has, nothing to decide.
                held = facts.segment(parent.targets[0])
                decision.report(
                    call,
                    code,
                    f"{facts.segment(call)} returns (obs, info) now: unpacked as `{held}, _ = {facts.segment(call)}`",
                    FixKind.ASSIST,
                    Tier.NOTE,
                )
            else:
                what = "(obs, info)" if target == "reset" else "(obs, reward, terminated, truncated, info)"
                called = f"{facts.segment(call.func)}()" if call in up else f"self.{target}()"
                decision.report(call, code, f"{called} returns {what} now: update how its result is used", FixKind.FLAG)
    decision.plan.unpack_self_reset = unpackable


def _base_resets_outside_reset(decision: ClassDecision, own_reset: Method | None, bases: frozenset[str]) -> list[ast.Call]:
    """``super().reset()`` and ``Base.reset(self)`` in the class's methods but its reset,
    where the base is a Gym env (its reset returns the pair once migrated, or Gymnasium's)."""
    receivers = decision.family.receivers
    found: list[ast.Call] = []
    for call in decision.index.nodes[ast.Call]:
        if not isinstance(call, ast.Call) or not isinstance(call.func, ast.Attribute) or not is_base_reset(call, bases):
            continue
        if own_reset is not None and method_of(decision, call) is own_reset:
            continue
        if decision.family.facts.enclosing_class(call) is not decision.classdef:
            continue  # a class nested in a method: its own bases
        if receivers.super_kind(call.func.value) is EnvKind.GYM_ENV:
            found.append(call)
    found.sort(key=lambda c: (c.lineno, c.col_offset))
    return found


def _super_reset_needs_seed(node: ast.AST, bases: frozenset[str]) -> bool:
    """An existing ``super().reset(...)`` that the build passes ``seed=seed`` (or drops ``return_info``)."""
    if not is_base_reset(node, bases):
        return False
    keywords = {k.arg for k in node.keywords}  # type: ignore[attr-defined]
    starred = None in keywords or any(isinstance(a, ast.Starred) for a in node.args)  # type: ignore[attr-defined]
    return "return_info" in keywords or ("seed" not in keywords and not starred)


def decide_published(decision: ClassDecision) -> bool:
    """A class that publishes gym < 0.9 hooks by class-level aliases (``reset = _reset``,
    often under ``if parse_version(gym.__version__) >= ...``): the hooks keep their names
    (the project's own API: subclasses call ``Base._reset(self)`` and expect the bare
    observation), and the ``reset`` alias becomes a real ``reset(self, *, seed=None,
    options=None)`` that seeds (``super().reset(seed=seed)``, then the seed hook as legacy
    ``seed(n)`` did) and returns ``(self._reset(), {})``. ``close``/``seed``/``configure``
    aliases keep working as they are; a ``render`` alias keeps render(mode) (one item).
    A class whose aliases this cannot make whole (``step = _step``, a reset hook that
    needs arguments, a public ``seed`` beside them) is left and reported once; True then."""
    published = decision.plan.published
    classdef = decision.classdef
    methods = decision.methods
    hook = published.get("reset")
    seed_hook = published.get("seed") or ("_seed" if "_seed" in methods else None)
    fits = "step" not in published
    if hook is not None:
        fits = fits and "seed" not in methods and "reset" not in methods and callable_without_arguments(methods[hook])
        if seed_hook is not None:
            params = param_names(methods[seed_hook])
            fits = fits and (len(params) >= 2 or methods[seed_hook].args.vararg is not None)
    if not fits:
        names = ", ".join(f"`{new} = {old}`" for new, old in published.items())
        decision.report(
            classdef,
            "GM504" if "step" in published else "GM501",
            f"`{classdef.name}` publishes its gym < 0.9 hooks by class-level aliases ({names}): left as they are (the hooks "
            "keep their names, which subclasses may call); give the public names Gymnasium's contracts by hand",
            FixKind.FLAG,
        )
        return True
    direct = decision.env.extends_gym_env_directly(classdef)
    if hook is not None:
        decision.plan.reset_alias = (hook, seed_hook, direct)
        seeds = f", seeds through `{seed_hook}` when given a seed" if seed_hook else ""
        first = "calls super().reset(seed=seed)" if direct else "does not call the base's reset"
        decision.report(
            decision.aliases["reset"],
            "GM501",
            f"`reset = {hook}` becomes a reset taking seed and options that {first}{seeds} and returns "
            f"`(self.{hook}(), {{}})`; `{hook}` keeps its name and its bare observation for the code that calls it",
        )
        if not direct and seed_hook is None and reads_np_random(decision.family.facts):
            decision.report(
                decision.aliases["reset"],
                "GM501",
                "reset() must seed np_random, but super().reset() here would also run the base env's own reset; call Env.reset(self, seed=seed) first by hand",
                FixKind.FLAG,
            )
    if "render" in published:
        decision.report(
            decision.aliases["render"],
            "GM405",
            f"`render = {published['render']}` keeps gym's render(mode): Gymnasium calls render() without arguments and takes "
            f"the mode from `render_mode` given at construction; make `{published['render']}` read `self.render_mode` "
            "(set in `__init__`) by hand",
            FixKind.FLAG,
        )
    return False


def private_reset_seed_hook(decision: ClassDecision, function: ast.AST) -> str | None:
    """``reset`` calls its base's private reset hook (``Base._reset(self)``,
    ``super()._reset()``) rather than the base's reset, so no seed reaches the base: the
    base's seed hook (``_seed``, kept beside its aliases) to call when given one."""
    inherited = decision.family.receivers.base_methods(decision.classdef)
    if "_reset" not in inherited or "_seed" not in inherited or "seed" in decision.methods or "_seed" in decision.methods:
        return None
    bases = {b.id for b in decision.classdef.bases if isinstance(b, ast.Name)} | {
        b.attr for b in decision.classdef.bases if isinstance(b, ast.Attribute)
    }
    for call in decision.function(function).of(ast.Call):
        func = call.func  # type: ignore[attr-defined]
        if not (isinstance(func, ast.Attribute) and func.attr == "_reset"):
            continue
        owner = func.value
        explicit = isinstance(owner, ast.Name) and owner.id in bases and len(call.args) == 1  # type: ignore[attr-defined]
        if explicit or is_super_method_call(call, "_reset"):
            return "_seed"
    return None


def _spelled(call: ast.AST) -> str:
    """How a base reset call is named in a message."""
    owner = call.func.value  # type: ignore[attr-defined]
    return f"{owner.id}.reset(self)" if isinstance(owner, ast.Name) else "super().reset()"


def _own_class_reset(decision: ClassDecision, function: ast.AST) -> str | None:
    """The class's own name where its reset calls ``Own.reset(self, ...)``."""
    own = frozenset({decision.classdef.name})
    # ``super().reset()`` is a base's reset, never the class's own
    calls = [c for c in walk(function) if isinstance(c, ast.Call) and not is_super_method_call(c, "reset")]
    return decision.classdef.name if any(is_base_reset(c, own) for c in calls) else None


def reset_bases(decision: ClassDecision) -> frozenset[str]:
    """The class's bases named plainly (``class Child(Base)``): ``Base.reset(self)`` in its
    reset is the base's reset, like ``super().reset()`` (its result is a pair once migrated,
    and it takes the seed)."""
    return frozenset(b.id for b in decision.classdef.bases if isinstance(b, ast.Name))


def is_base_reset(node: ast.AST | None, bases: frozenset[str]) -> bool:
    """``super().reset(...)``, or ``Base.reset(self, ...)`` for a base in ``bases``
    (``cst_edits.is_base_reset`` on the build's side)."""
    if is_super_method_call(node, "reset"):
        return True
    return (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == "reset"
        and isinstance(node.func.value, ast.Name)
        and node.func.value.id in bases
        and bool(node.args)
        and isinstance(node.args[0], ast.Name)
        and node.args[0].id == "self"
    )
